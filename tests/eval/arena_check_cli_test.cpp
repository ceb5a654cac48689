// `sarmap simulate`, `run` and `eval` end to end on the tiny arena: the
// sequence records its arena's hash, the run's manifest carries it, and eval
// scores the run against that arena only (naming both when given another).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/io/sha256.hpp"
#include "tests/cli/tiny_arena.hpp"
#include "tests/sim/run_cli.hpp"

namespace sarmap::eval {
namespace {

namespace fs = std::filesystem;

using testing::kTinyArena;
const std::string kOtherArena = SARMAP_SOURCE_DIR "/tests/cli/data/room_with_door.json";

// One simulated sequence and its run, shared by the tests (each copies what it changes).
class ArenaCheckCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = testing::scratch_dir("arena_check_cli");
    auto r =
        testing::run_cli("simulate " + kTinyArena + " --out " + (dir_ / "seq").string() + " --quiet", dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = testing::run_cli("run " + (dir_ / "seq").string() + " --out " + (dir_ / "run").string() +
                             " --voxel 0.1 --classifier labels --quiet",
                         dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static testing::CliResult eval(const std::string& arena, const fs::path& run) {
    return testing::run_cli("eval --arena " + arena + " --run " + run.string() + " --json", dir_);
  }

  static fs::path dir_;
};

fs::path ArenaCheckCli::dir_;

TEST_F(ArenaCheckCli, TheSequenceAndTheManifestRecordTheArena) {
  const std::string tiny = digest_file(kTinyArena).sha256;
  const auto sequence = nlohmann::json::parse(testing::slurp(dir_ / "seq" / "sequence.json"));
  EXPECT_EQ(sequence.at("arena_sha256"), tiny);
  const auto manifest = nlohmann::json::parse(testing::slurp(dir_ / "run" / "manifest.json"));
  EXPECT_EQ(manifest.at("arena_sha256"), tiny);
  EXPECT_EQ(manifest.at("input").at("path"), fs::absolute(dir_ / "seq").string());
}

TEST_F(ArenaCheckCli, TheRunsArenaIsScored) {
  const auto r = eval(kTinyArena, dir_ / "run");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("arena_checked"), true);
  // Within one voxel: the strict recall depends on which side of a voxel face
  // the floor's hits fall, which differs between Embree's SIMD kernels
  // (voxel_eval_cli_test.cpp).
  EXPECT_GT(j.at("voxel_recall_within_1").get<double>(), 0.99);
}

TEST_F(ArenaCheckCli, AnotherArenaIsRefusedNamingBoth) {
  const std::string tiny = digest_file(kTinyArena).sha256;
  auto r = eval(kOtherArena, dir_ / "run");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.out.empty()) << r.out;  // no figures at all
  EXPECT_NE(r.err.find("sarmap: error: run " + (dir_ / "run").string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sha256 " + tiny), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("arena " + kOtherArena + " (\"room-with-door-4x3\") has sha256 " +
                       digest_file(kOtherArena).sha256),
            std::string::npos)
      << r.err;

  // A copy of the arena with one wall moved, under the same name.
  std::string text = testing::slurp(kTinyArena);
  const std::string wall = "\"from\": [0, 1.8], \"to\": [3, 1.8]";
  ASSERT_NE(text.find(wall), std::string::npos);
  text.replace(text.find(wall), wall.size(), "\"from\": [0, 1.5], \"to\": [3, 1.5]");
  std::ofstream(dir_ / "moved_wall.json", std::ios::binary) << text;
  r = eval((dir_ / "moved_wall.json").string(), dir_ / "run");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(
      r.err.find("moved_wall.json (\"tiny-3x2\") has sha256 " + digest_file(dir_ / "moved_wall.json").sha256),
      std::string::npos)
      << r.err;
}

// A sequence without arena_sha256 (a recording, an older simulation) still
// runs, its manifest names no arena, and eval scores it with a note.
TEST_F(ArenaCheckCli, ARunWithoutArenaIsScoredWithANote) {
  const fs::path seq = dir_ / "plain_seq", run = dir_ / "plain_run";
  fs::copy(dir_ / "seq", seq);
  auto sequence = nlohmann::ordered_json::parse(testing::slurp(seq / "sequence.json"));
  sequence.erase("arena_sha256");
  fs::remove(seq / "sequence.json");
  std::ofstream(seq / "sequence.json") << sequence.dump();
  auto r = testing::run_cli(
      "run " + seq.string() + " --out " + run.string() + " --voxel 0.1 --classifier labels --quiet", dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(nlohmann::json::parse(testing::slurp(run / "manifest.json")).contains("arena_sha256"));
  r = eval(kTinyArena, run);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("arena_checked"), false);
  EXPECT_NE(j.at("notes").dump().find("records no arena"), std::string::npos) << j.at("notes");
}

}  // namespace
}  // namespace sarmap::eval
