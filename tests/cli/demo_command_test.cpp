// `sarmap demo` end to end on a tiny arena: simulate, run, eval and summary,
// then the cached sequence reused, and simulated again when its inputs change.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/io/run_folder.hpp"
#include "tests/cli/cli_runner.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::run_cli;

class DemoCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sarmap_demo_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A copy, so the test can change the arena's bytes.
    fs::copy_file(fs::path(SARMAP_SOURCE_DIR) / "tests" / "cli" / "data" / "tiny_arena.json", arena_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  test::CliResult demo(const std::string& extra = "") {
    return run_cli(
        "demo --arena " + quoted(arena_.string()) + " --out " + quoted(out_.string()) + " --quiet" +
            " --classifier labels" + extra,
        dir_);
  }
  fs::path dir_;
  fs::path arena_ =
      fs::temp_directory_path() / ("sarmap_demo_cli_" + std::to_string(::getpid())) / "tiny.json";
  fs::path out_ = fs::temp_directory_path() / ("sarmap_demo_cli_" + std::to_string(::getpid())) / "demo";
};

TEST_F(DemoCommand, RunsEveryStageAndPrintsASummary) {
  const auto r = demo();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("simulated now"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("3 scans"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("voxels    precision"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("class accuracy"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find((out_ / "run").string()), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out_ / "sequence" / "sequence.json"));
  EXPECT_TRUE(fs::exists(out_ / "sequence.stamp"));
  for (const char* f : {"map.sarmap", "map.bt", "map.ot", "voxels.ply", "semantic_points.ply",
                        "segments.json", "segments.ply", "graph.json", "graph.graphml", "graph.ply",
                        "grid.pgm", "grid.yaml", "manifest.json", "profile.json", "summary.json"}) {
    EXPECT_TRUE(fs::exists(out_ / "run" / f)) << f;
  }
  const auto eval = nlohmann::json::parse(test::read_all(out_ / "eval.json"));
  EXPECT_EQ(eval.at("arena").get<std::string>(), "tiny-3x2");
  EXPECT_GT(eval.at("voxel_precision_within_1").get<double>(), 0.95);
  EXPECT_GT(eval.at("voxel_class_accuracy").get<double>(), 0.9);
  EXPECT_DOUBLE_EQ(eval.at("accuracy").get<double>(), 1.0);  // the labels classifier passes the truth through
  EXPECT_EQ(eval.at("arena_checked"), true);  // the sequence named its arena, and it is this one
}

// The pictures of `sarmap render` beside the run's outputs, outside its
// manifest (the folder still verifies), and with snapshots the growth strip.
TEST_F(DemoCommand, DrawsPicturesOfTheMaps) {
  auto r = demo(" --snapshots 1,2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("pictures  "), std::string::npos) << r.out;
  EXPECT_TRUE(fs::is_regular_file(out_ / "run" / "render.png"));
  EXPECT_TRUE(fs::is_regular_file(out_ / "run" / "growth.png"));
  EXPECT_TRUE(fs::is_directory(out_ / "run" / "snap_0001"));
  EXPECT_NO_THROW(verify_run_folder(out_ / "run"));
  // Again without snapshots: no strip of snapshots that are gone.
  r = demo();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(out_ / "run" / "render.png"));
  EXPECT_FALSE(fs::exists(out_ / "run" / "growth.png"));
}

// The run's summary.json gains eval's headline figures, each as `sarmap eval
// --json` gives it for the same run, and the run folder still verifies.
TEST_F(DemoCommand, AddsEvalsFiguresToTheRunsSummary) {
  ASSERT_EQ(demo().exit_code, 0);
  EXPECT_NO_THROW(verify_run_folder(out_ / "run"));
  const auto summary = nlohmann::json::parse(test::read_all(out_ / "run" / "summary.json"));
  EXPECT_EQ(summary.at("scans").get<int>(), 3);  // the run's own figures stay
  ASSERT_TRUE(summary.contains("eval")) << summary.dump(2);
  const nlohmann::json& figures = summary.at("eval");

  const auto r = run_cli("eval --arena " + quoted(arena_.string()) + " --run " + quoted((out_ / "run").string()) +
                             " --json --quiet",
                         dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto eval = nlohmann::json::parse(r.out);
  for (const char* key : {"arena", "arena_checked", "accuracy", "mean_iou", "per_class_iou", "voxel_precision",
                          "voxel_recall", "voxel_f1", "voxel_class_accuracy", "segments", "graph", "notes"}) {
    EXPECT_TRUE(figures.contains(key)) << key;
  }
  for (const auto& [key, value] : figures.items()) {
    ASSERT_TRUE(eval.contains(key)) << key;
    if (!value.is_object()) {
      EXPECT_EQ(value, eval.at(key)) << key;
      continue;
    }
    EXPECT_FALSE(value.empty()) << key;
    for (const auto& [inner, figure] : value.items()) EXPECT_EQ(figure, eval.at(key).at(inner)) << key << "." << inner;
  }
  EXPECT_EQ(figures.at("segments").at("segment_count"), summary.at("segments").at("count"));
  EXPECT_EQ(figures.at("graph").at("nodes"), summary.at("topo_map").at("nodes"));
}

TEST_F(DemoCommand, ReusesTheCachedSequenceUntilItsInputsChange) {
  ASSERT_EQ(demo().exit_code, 0);
  const auto frame = out_ / "sequence" / "frame_000000.ply";
  const auto first_write = fs::last_write_time(frame);
  const std::string stamp = test::read_all(out_ / "sequence.stamp");

  auto r = demo();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("cached"), std::string::npos) << r.out;
  EXPECT_EQ(fs::last_write_time(frame), first_write);
  EXPECT_EQ(test::read_all(out_ / "sequence.stamp"), stamp);

  // Another noise seed, then another arena file: simulated again each time.
  r = demo(" --seed 7");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("simulated now"), std::string::npos) << r.out;
  const std::string seed_stamp = test::read_all(out_ / "sequence.stamp");
  EXPECT_NE(seed_stamp, stamp);
  std::ofstream(arena_, std::ios::app) << "\n";
  r = demo(" --seed 7");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("simulated now"), std::string::npos) << r.out;
  EXPECT_NE(test::read_all(out_ / "sequence.stamp"), seed_stamp);

  // A sequence whose stamp is gone (an interrupted simulation) is not trusted.
  fs::remove(out_ / "sequence.stamp");
  r = demo(" --seed 7");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("simulated now"), std::string::npos) << r.out;

  // Nor one cached before sequences recorded their arena (a stamp without
  // arena_sha256): simulated again, so that eval can check the arena.
  auto old_stamp = nlohmann::ordered_json::parse(test::read_all(out_ / "sequence.stamp"));
  ASSERT_EQ(old_stamp.erase("arena_sha256"), 1u);
  fs::remove(out_ / "sequence.stamp");
  std::ofstream(out_ / "sequence.stamp", std::ios::binary) << old_stamp.dump() << "\n";
  r = demo(" --seed 7");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("simulated now"), std::string::npos) << r.out;
  EXPECT_EQ(nlohmann::json::parse(test::read_all(out_ / "eval.json")).at("arena_checked"), true);
}

TEST_F(DemoCommand, BadArenaIsAnError) {
  const auto r = run_cli("demo --arena " + quoted((dir_ / "nope.json").string()) + " --out " +
                             quoted(out_.string()) + " --quiet",
                         dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nope.json"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace sarmap
