// Entry point of the `sarmap` CLI: registers the subcommands and turns a
// sarmap::Error into a message on stderr and a non-zero exit code.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>

#include <CLI/CLI.hpp>

#include "engine/core/error.hpp"
#include "engine/core/version.hpp"
#include "tools/sarmap/commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sarmap: semantic, metric and topological maps of search-and-rescue arenas"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("sarmap ") + sarmap::kVersion);

  // One line per subcommand (tools/sarmap/<name>_command.cpp).
  // (none registered yet)
  sarmap::cli::add_info_command(app);
  sarmap::cli::add_convert_command(app);
  sarmap::cli::add_simulate_command(app);
  sarmap::cli::add_eval_command(app);
  sarmap::cli::add_run_command(app);
  sarmap::cli::add_demo_command(app);
  sarmap::cli::add_classify_command(app);
  sarmap::cli::add_plan_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const sarmap::Error& e) {
    std::fprintf(stderr, "sarmap: error: %s\n", e.what());
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    // A folder that cannot be made or read is the user's to fix, not a bug.
    std::fprintf(stderr, "sarmap: error: %s: %s\n", e.path1().string().c_str(), e.code().message().c_str());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "sarmap: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sarmap: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
