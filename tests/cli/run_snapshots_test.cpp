// `sarmap run --snapshots`: each snapshot is a whole output folder holding the
// maps as a run cut at that scan would have them; a rerun removes the
// snapshots it does not write again and nothing else; bad counts are refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/io/run_folder.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/cli/tiny_arena.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::read_all;
using test::run_cli;

using testing::kTinyArena;

class RunSnapshots : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto r = run_cli("simulate " + quoted(kTinyArena) + " --out " + quoted(seq().string()) + " --quiet",
                           scratch_.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  fs::path seq() const { return scratch_ / "seq"; }
  test::CliResult run(const fs::path& input, const fs::path& out, const std::string& options) const {
    return run_cli("run " + quoted(input.string()) + " --out " + quoted(out.string()) +
                       " --classifier labels --voxel 0.1 --quiet " + options,
                   scratch_.path());
  }
  test::ScratchFolder scratch_;
};

TEST_F(RunSnapshots, ASnapshotHoldsTheMapsOfARunCutThere) {
  const auto r = run(seq(), scratch_ / "run", "--snapshots 2,1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"snap_0001", "snap_0002"}) EXPECT_NO_THROW(verify_run_folder(scratch_ / "run" / name));
  EXPECT_EQ(nlohmann::json::parse(read_all(scratch_ / "run" / "snap_0002" / "manifest.json")).at("scans"), 2);

  // The same sequence with its last frame left out.
  fs::create_directories(scratch_ / "cut");
  for (const char* frame : {"frame_000000.ply", "frame_000001.ply"}) fs::copy(seq() / frame, scratch_ / "cut" / frame);
  auto sequence = nlohmann::ordered_json::parse(read_all(seq() / "sequence.json"));
  ASSERT_EQ(sequence.at("frames").size(), 3u);
  sequence.at("frames").erase(2);
  scratch_.write("cut/sequence.json", sequence.dump());
  ASSERT_EQ(run(scratch_ / "cut", scratch_ / "cut_run", "").exit_code, 0);
  for (const char* name : {"map.sarmap", "voxels.ply", "semantic_points.ply", "segments.json", "graph.json"}) {
    EXPECT_TRUE(read_all(scratch_ / "run" / "snap_0002" / name) == read_all(scratch_ / "cut_run" / name)) << name;
  }
  // Its summary.json too, listed in its manifest, and its figures but for the timings.
  const auto outputs = nlohmann::json::parse(read_all(scratch_ / "run" / "snap_0002" / "manifest.json")).at("outputs");
  EXPECT_EQ(outputs.back().at("name").get<std::string>(), "summary.json");
  const auto figures = [](const fs::path& folder) {
    auto summary = nlohmann::json::parse(read_all(folder / "summary.json"));
    for (const char* timing : {"wall_s", "scans_per_second", "stages", "latency"}) summary.erase(timing);
    return summary;
  };
  EXPECT_EQ(figures(scratch_ / "run" / "snap_0002").at("scans"), 2);
  EXPECT_EQ(figures(scratch_ / "run" / "snap_0002"), figures(scratch_ / "cut_run"));
  EXPECT_EQ(figures(scratch_ / "run").at("scans"), 3);
  // And the final maps are not the snapshot's.
  EXPECT_FALSE(read_all(scratch_ / "run" / "map.sarmap") == read_all(scratch_ / "run" / "snap_0002" / "map.sarmap"));
}

// The stages overlap by default: a snapshot ends one stretch of overlapped
// scans and starts the next. Running them in order changes no output.
TEST_F(RunSnapshots, OverlappedStagesWriteTheSameOutputsAsInOrder) {
  ASSERT_EQ(run(seq(), scratch_ / "overlap", "--snapshots 1,2").exit_code, 0);
  ASSERT_EQ(run(seq(), scratch_ / "in_order", "--snapshots 1,2 --no-overlap --threads 1").exit_code, 0);
  for (const char* folder : {"snap_0001", "snap_0002", "."}) {
    for (const char* name : {"map.sarmap", "voxels.ply", "semantic_points.ply", "segments.json", "graph.json"}) {
      EXPECT_TRUE(read_all(scratch_ / "overlap" / folder / name) == read_all(scratch_ / "in_order" / folder / name))
          << folder << "/" << name;
    }
  }
}

TEST_F(RunSnapshots, ARerunRemovesOnlyTheSnapshotsItDoesNotWriteAgain) {
  ASSERT_EQ(run(seq(), scratch_ / "run", "--snapshots 1,2").exit_code, 0);
  scratch_.write("run/snap_notes/notes.txt", "kept");
  scratch_.write("run/snap_0007", "a file, not a snapshot folder");
  ASSERT_EQ(run(seq(), scratch_ / "run", "--snapshots 1").exit_code, 0);
  EXPECT_TRUE(fs::exists(scratch_ / "run" / "snap_0001" / "manifest.json"));
  EXPECT_FALSE(fs::exists(scratch_ / "run" / "snap_0002"));
  EXPECT_TRUE(fs::exists(scratch_ / "run" / "snap_notes" / "notes.txt"));
  EXPECT_TRUE(fs::exists(scratch_ / "run" / "snap_0007"));
  ASSERT_EQ(run(seq(), scratch_ / "run", "").exit_code, 0);
  EXPECT_FALSE(fs::exists(scratch_ / "run" / "snap_0001"));
}

TEST_F(RunSnapshots, CountsOutsideTheRunAreWarnedOrRefused) {
  auto r = run(seq(), scratch_ / "run", "--snapshots 2,9");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("sarmap: warning: no snapshot after 9 scans: the run mapped 3"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(scratch_ / "run" / "snap_0002"));
  r = run(seq(), scratch_ / "zero", "--snapshots 0");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--snapshots takes scan counts of 1 or more"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(scratch_ / "zero"));
  r = run(seq(), scratch_ / "negative", "--snapshots -1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--snapshots"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace sarmap
