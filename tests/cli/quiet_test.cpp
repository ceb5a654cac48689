// `--quiet`, which the README promises on every subcommand: each takes it,
// and it silences what the command prints besides its result.
#include <gtest/gtest.h>

#include <string>

#include "tests/cli/cli_runner.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/semantic/fixture_model.hpp"

namespace sarmap {
namespace {

using test::quoted;
using test::run_cli;

const std::string kData = SARMAP_TEST_DATA_DIR;

TEST(Quiet, EverySubcommandTakesIt) {
  test::ScratchFolder scratch;
  for (const char* command : {"demo", "run", "plan", "eval", "simulate", "classify", "info", "convert", "view"}) {
    const auto r = run_cli(std::string(command) + " --help", scratch.path());
    EXPECT_EQ(r.exit_code, 0) << command << ": " << r.err;
    EXPECT_NE(r.out.find("--quiet"), std::string::npos) << command << ": " << r.out;
  }
}

// classify's summary line goes; the labelled cloud it writes does not change.
// One point, so one block of the network runs (a quarter of a second).
TEST(Quiet, SilencesClassifysSummary) {
  test::ScratchFolder scratch;
  const auto cloud = scratch.write(
      "one.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                 "end_header\n0.5 0.5 0.1\n");
  const std::string args = "classify " + quoted(cloud.string()) + " --model " +
                           quoted(test::fixture_model_c6().string()) + " --min-points 1 --out ";
  const auto loud = run_cli(args + quoted((scratch / "loud.ply").string()), scratch.path());
  ASSERT_EQ(loud.exit_code, 0) << loud.err;
  EXPECT_NE(loud.out.find("classified 1 points in 1 blocks"), std::string::npos) << loud.out;
  const auto quiet = run_cli(args + quoted((scratch / "quiet.ply").string()) + " --quiet", scratch.path());
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.out, "");
  EXPECT_EQ(quiet.err, "");
  EXPECT_EQ(test::read_all(scratch / "quiet.ply"), test::read_all(scratch / "loud.ply"));
}

// eval prints no progress, only its figures, which are its result: --quiet is
// taken and the figures are the same.
TEST(Quiet, LeavesEvalsFiguresAsTheyAre) {
  test::ScratchFolder scratch;
  const std::string arena = quoted(std::string(SARMAP_SOURCE_DIR) + "/tests/cli/data/tiny_arena.json");
  const std::string sequence = quoted((scratch / "sequence").string());
  const std::string run = quoted((scratch / "run").string());
  ASSERT_EQ(run_cli("simulate " + arena + " --out " + sequence + " --quiet", scratch.path()).exit_code, 0);
  const auto mapped = run_cli("run " + sequence + " --out " + run + " --classifier labels --voxel 0.1 --quiet",
                              scratch.path());
  ASSERT_EQ(mapped.exit_code, 0) << mapped.err;
  const std::string eval = "eval --arena " + arena + " --run " + run;
  const auto loud = run_cli(eval, scratch.path());
  ASSERT_EQ(loud.exit_code, 0) << loud.err;
  ASSERT_NE(loud.out.find("tiny-3x2"), std::string::npos) << loud.out;
  const auto quiet = run_cli(eval + " --quiet", scratch.path());
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.out, loud.out);
  EXPECT_EQ(quiet.err, "");
}

}  // namespace
}  // namespace sarmap
