// What a user who mistypes sees: usage errors (an unknown subcommand, a
// missing argument, a value an option refuses) say "sarmap: error:" and
// exit with 2, apart from the exit 1 of an error in the work itself; help
// shows the off switches as they are typed.
#include <gtest/gtest.h>

#include <string>

#include "tests/cli/cli_runner.hpp"
#include "tests/io/scratch_folder.hpp"

namespace sarmap {
namespace {

using test::run_cli;

TEST(UsageErrors, AnUnknownSubcommandIsNamedWithTheKnownOnes) {
  test::ScratchFolder scratch;
  const auto r = run_cli("bogus", scratch.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("sarmap: error: unknown subcommand 'bogus' (the subcommands: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("run"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Run with --help"), std::string::npos) << r.err;
}

TEST(UsageErrors, MissingArgumentsAndRefusedValuesExitWithTwo) {
  test::ScratchFolder scratch;
  auto r = run_cli("run", scratch.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("sarmap: error: INPUT is required"), std::string::npos) << r.err;
  r = run_cli("run in --out out --voxel nan", scratch.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("sarmap: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--voxel"), std::string::npos) << r.err;
  r = run_cli("run in --out out --no-such-option", scratch.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--no-such-option"), std::string::npos) << r.err;
  // An error in the work itself is exit 1.
  r = run_cli("run " + (scratch / "missing").string() + " --out " + (scratch / "out").string(), scratch.path());
  EXPECT_EQ(r.exit_code, 1) << r.err;
}

TEST(UsageErrors, HelpAndVersionAreNotErrors) {
  test::ScratchFolder scratch;
  auto r = run_cli("--help", scratch.path());
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("Subcommands:"), std::string::npos) << r.out;
  r = run_cli("--version", scratch.path());
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("sarmap "), std::string::npos) << r.out;
  for (const char* command : {"run", "classify"}) {
    r = run_cli(std::string(command) + " --help", scratch.path());
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("--disable-rule NAME"), std::string::npos) << command << ": " << r.out;
    EXPECT_EQ(r.out.find("{false}"), std::string::npos) << command << ": " << r.out;
  }
}

}  // namespace
}  // namespace sarmap
