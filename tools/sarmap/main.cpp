// Entry point of the `sarmap` CLI: registers the subcommands and turns a
// sarmap::Error into a message on stderr and exit code 1, a usage error
// (unknown subcommand or option, a value a check refuses) into one with
// exit code 2.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>

#include <CLI/CLI.hpp>

#include "engine/core/error.hpp"
#include "engine/core/version.hpp"
#include "tools/sarmap/commands.hpp"

namespace {

// CLI11's message, except for a first word that names no subcommand, where
// CLI11 would only say that a subcommand is required.
std::string usage_error(const CLI::App& app, int argc, char** argv, const CLI::ParseError& e) {
  if (argc < 2 || argv[1][0] == '-') return e.what();
  std::string names;
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_name() == argv[1]) return e.what();
    names += (names.empty() ? "" : ", ") + sub->get_name();
  }
  return std::string("unknown subcommand '") + argv[1] + "' (the subcommands: " + names + ")";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sarmap: semantic, metric and topological maps of search-and-rescue arenas"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("sarmap ") + sarmap::kVersion);

  // One line per subcommand (tools/sarmap/<name>_command.cpp).
  sarmap::cli::add_info_command(app);
  sarmap::cli::add_convert_command(app);
  sarmap::cli::add_simulate_command(app);
  sarmap::cli::add_eval_command(app);
  sarmap::cli::add_run_command(app);
  sarmap::cli::add_demo_command(app);
  sarmap::cli::add_classify_command(app);
  sarmap::cli::add_plan_command(app);
  sarmap::cli::add_render_command(app);
  sarmap::cli::add_view_command(app);
  sarmap::cli::add_merge_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::fprintf(stderr, "sarmap: error: %s\nRun with --help for more information.\n",
                 usage_error(app, argc, argv, e).c_str());
    return 2;
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
