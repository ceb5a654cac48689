// Tests of evaluate_run's arena check (engine/eval/run_evaluation.hpp) on
// tiny synthetic run folders: a manifest's arena_sha256 must be the given
// arena's, and a run that records none is scored with a note.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/eval/run_evaluation.hpp"
#include "engine/io/ply.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/io/sha256.hpp"
#include "tests/cli/tiny_arena.hpp"
#include "tests/sim/run_cli.hpp"

namespace sarmap::eval {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using testing::kTinyArena;
const fs::path kOtherArena = SARMAP_SOURCE_DIR "/tests/cli/data/room_with_door.json";

class ArenaCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::scratch_dir(std::string("arena_check_") +
                                ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A run folder of two labelled points whose manifest holds `manifest`'s members.
  fs::path write_run(const nlohmann::ordered_json& manifest) {
    const fs::path run = dir_ / "run";
    fs::create_directories(run);
    PointBuffer p(2);
    p.enable_labels();
    p.enable_gt_labels();
    for (std::size_t i = 0; i < 2; ++i) p.labels()[i] = p.gt_labels()[i] = 1;
    RunFolderWriter folder(run);
    write_ply(run / "semantic_points.ply", p);
    folder.commit(manifest, {"semantic_points.ply"});
    return run;
  }

  static std::string error_of(const sim::Arena& arena, const fs::path& run) {
    try {
      evaluate_run(arena, run);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
      return e.what();
    }
    return "(no error)";
  }

  fs::path dir_;
};

TEST_F(ArenaCheck, TheRunsOwnArenaIsScored) {
  const std::string tiny = digest_file(kTinyArena).sha256;
  const fs::path run =
      write_run({{"input", {{"path", "/seq"}, {"sha256", nullptr}}}, {"arena_sha256", tiny}});
  const RunEvaluation e = evaluate_run(sim::load_arena(kTinyArena), run);
  EXPECT_TRUE(e.arena_checked);
  ASSERT_TRUE(e.points);
  EXPECT_EQ(e.points->scored, 2u);
  EXPECT_EQ(nlohmann::json::parse(format_json(e)).at("arena_checked"), true);
}

TEST_F(ArenaCheck, AnotherArenaIsRefusedNamingBoth) {
  const std::string tiny = digest_file(kTinyArena).sha256;
  const fs::path run =
      write_run({{"input", {{"path", "/data/tiny_seq"}, {"sha256", nullptr}}}, {"arena_sha256", tiny}});
  const sim::Arena other = sim::load_arena(kOtherArena);
  const std::string message = error_of(other, run);
  EXPECT_THAT(message, HasSubstr("run " + run.string()));
  EXPECT_THAT(message, HasSubstr("/data/tiny_seq"));
  EXPECT_THAT(message, HasSubstr("sha256 " + tiny));
  EXPECT_THAT(message, HasSubstr("arena " + kOtherArena.string()));
  EXPECT_THAT(message, HasSubstr("has sha256 " + digest_file(kOtherArena).sha256));
  // A copy of the run's arena changed in one byte is another arena too.
  const sim::Arena changed = sim::parse_arena(sarmap::testing::slurp(kTinyArena) + "\n", "changed.json", ".");
  EXPECT_THAT(error_of(changed, run), HasSubstr("arena changed.json"));
}

TEST_F(ArenaCheck, ARunWithoutArenaIsScoredWithANote) {
  const fs::path run = write_run({{"input", {{"path", "/recording"}, {"sha256", nullptr}}}});
  const RunEvaluation e = evaluate_run(sim::load_arena(kOtherArena), run);
  EXPECT_FALSE(e.arena_checked);
  ASSERT_TRUE(e.points);
  EXPECT_EQ(e.points->scored, 2u);
  EXPECT_THAT(format_table(e), HasSubstr("note: the run's input records no arena"));
  EXPECT_EQ(nlohmann::json::parse(format_json(e)).at("arena_checked"), false);
}

TEST_F(ArenaCheck, AnArenaBuiltInCodeIsNotCheckedAndABadHashIsAnError) {
  const fs::path run = write_run({{"arena_sha256", digest_file(kTinyArena).sha256}});
  sim::Arena in_code = sim::load_arena(kOtherArena);
  in_code.sha256.clear();
  const RunEvaluation e = evaluate_run(in_code, run);
  EXPECT_FALSE(e.arena_checked);
  EXPECT_THAT(format_table(e), HasSubstr("the arena was not read from a file"));

  fs::remove_all(run);
  const fs::path bad = write_run({{"arena_sha256", "ABC"}});
  try {
    evaluate_run(sim::load_arena(kTinyArena), bad);
    ADD_FAILURE() << "a malformed arena_sha256 was accepted";
  } catch (const Error& err) {
    EXPECT_EQ(err.code(), ErrorCode::InvalidData);
    EXPECT_THAT(err.what(), HasSubstr("manifest.json: arena_sha256: expected 64 lowercase hex digits"));
  }
}

}  // namespace
}  // namespace sarmap::eval
