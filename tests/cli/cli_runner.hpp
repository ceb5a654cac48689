// Runs the built `sarmap` binary (SARMAP_CLI_PATH) through the shell and
// captures its exit code, stdout and stderr, as a user or a script would see
// them. stderr goes to a file, so the CLI sees a non-terminal there.
#pragma once

#include <sys/wait.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace sarmap::test {

struct CliResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string quoted(const std::string& arg) {
  std::string q = "'";
  for (const char c : arg) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

inline std::string read_all(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// `args` is appended to the command line verbatim (quote paths with quoted()).
inline CliResult run_binary(const std::filesystem::path& binary, const std::string& args,
                            const std::filesystem::path& scratch) {
  const auto out = scratch / "cli_stdout.txt";
  const auto err = scratch / "cli_stderr.txt";
  const std::string command = quoted(binary.string()) + " " + args + " >" + quoted(out.string()) + " 2>" +
                              quoted(err.string()) + " </dev/null";
  const int status = std::system(command.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_all(out);
  r.err = read_all(err);
  return r;
}

// The built binary, as above.
inline CliResult run_cli(const std::string& args, const std::filesystem::path& scratch) {
  return run_binary(SARMAP_CLI_PATH, args, scratch);
}

}  // namespace sarmap::test
