// Runs the built `sarmap` binary for CLI tests and captures its exit code,
// stdout and stderr.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "tests/file_bytes.hpp"

namespace sarmap::testing {

using sarmap::test::slurp;

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

// `args` is appended to the binary's path as is (quote paths with spaces).
inline CliResult run_cli(const std::string& args, const std::filesystem::path& scratch) {
  const auto out = scratch / "cli_stdout.txt";
  const auto err = scratch / "cli_stderr.txt";
  const std::string command = std::string(SARMAP_CLI_PATH) + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(command.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("sarmap_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace sarmap::testing
