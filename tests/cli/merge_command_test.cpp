// `sarmap merge`: runs written with `--keep-state` merge into one whole run
// folder; the parts of a sequence merge into the whole sequence's kept points
// and known space; a run carried by --transform lands where the transform
// says; runs that cannot merge, and bad options, are refused naming why,
// before the output folder is touched.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/core/classes.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/metric/map_file.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/cli/tiny_arena.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/release_only.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::read_all;
using test::run_cli;

using testing::kTinyArena;

nlohmann::json json_of(const fs::path& file) { return nlohmann::json::parse(read_all(file)); }

std::size_t known_voxels(const fs::path& run) { return metric::load_map(run / "map.sarmap").counts().known; }

class MergeCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto r = run_cli("simulate " + quoted(kTinyArena) + " --out " + quoted(seq().string()) + " --quiet",
                           scratch_.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  fs::path seq() const { return scratch_ / "seq"; }
  // The simulated sequence cut to frames [first, last).
  fs::path part(std::size_t first, std::size_t last) const {
    const fs::path folder = scratch_ / ("part_" + std::to_string(first) + "_" + std::to_string(last));
    fs::create_directories(folder);
    auto sequence = nlohmann::ordered_json::parse(read_all(seq() / "sequence.json"));
    auto frames = nlohmann::ordered_json::array();
    for (std::size_t f = first; f < last; ++f) {
      frames.push_back(sequence.at("frames").at(f));
      const std::string file = sequence.at("frames").at(f).at("file").get<std::string>();
      fs::copy(seq() / file, folder / file);
    }
    sequence["frames"] = frames;
    scratch_.write(folder.lexically_relative(scratch_.path()).string() + "/sequence.json", sequence.dump());
    return folder;
  }
  test::CliResult run(const fs::path& input, const fs::path& out,
                      const std::string& options = "--keep-state --classifier labels --voxel 0.1") const {
    return run_cli("run " + quoted(input.string()) + " --out " + quoted(out.string()) + " --quiet " + options,
                   scratch_.path());
  }
  test::CliResult merge(const std::string& args) const { return run_cli("merge " + args, scratch_.path()); }
  test::ScratchFolder scratch_;
};

// The library's merge has its own tests under the sanitizers
// (tests/pipeline/mapper_merge_test.cpp); these end-to-end cases run in
// the release build, the refusals below everywhere.
TEST_F(MergeCommand, ThePartsOfASequenceMergeIntoTheWholeSequencesRun) {
  RELEASE_ONLY();
  ASSERT_EQ(run(seq(), scratch_ / "whole").exit_code, 0);
  ASSERT_EQ(run(part(0, 2), scratch_ / "a").exit_code, 0);
  ASSERT_EQ(run(part(2, 3), scratch_ / "b").exit_code, 0);
  const auto r = merge(quoted((scratch_ / "a").string()) + " " + quoted((scratch_ / "b").string()) + " --out " +
                       quoted((scratch_ / "merged").string()) + " --keep-state");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("merged"), std::string::npos) << r.out;
  ASSERT_NO_THROW(verify_run_folder(scratch_ / "merged"));
  const auto manifest = json_of(scratch_ / "merged" / "manifest.json");
  EXPECT_EQ(manifest.at("layout"), "merged");
  EXPECT_EQ(manifest.at("scans"), 3);
  ASSERT_EQ(manifest.at("input").at("runs").size(), 2u);
  EXPECT_EQ(manifest.at("input").at("runs").at(1).at("scans"), 1);
  EXPECT_EQ(manifest.at("arena_sha256"), json_of(scratch_ / "whole" / "manifest.json").at("arena_sha256"));
  EXPECT_EQ(manifest.at("outputs").back().at("name"), "mapper.state");
  // The first part's points come first, as in the whole run; every voxel the
  // whole run knows is known.
  EXPECT_TRUE(read_all(scratch_ / "merged" / "semantic_points.ply") ==
              read_all(scratch_ / "whole" / "semantic_points.ply"));
  EXPECT_EQ(known_voxels(scratch_ / "merged"), known_voxels(scratch_ / "whole"));
  // A merged run merges again (it kept its state).
  const auto again = merge(quoted((scratch_ / "merged").string()) + " " + quoted((scratch_ / "a").string()) +
                           " --out " + quoted((scratch_ / "again").string()) + " --quiet");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_TRUE(again.out.empty()) << again.out;
  EXPECT_EQ(known_voxels(scratch_ / "again"), known_voxels(scratch_ / "whole"));
}

// The default classifier labels the accumulated map: the merged run's kept
// points take their classes from the merged labelled point map, as the
// whole run's do from its own.
TEST_F(MergeCommand, DgcnnRunsMergeWithTheirClasses) {
  RELEASE_ONLY();
  const std::string dgcnn = "--keep-state --classifier dgcnn --voxel 0.1";
  ASSERT_EQ(run(seq(), scratch_ / "whole", dgcnn).exit_code, 0);
  ASSERT_EQ(run(part(0, 2), scratch_ / "a", dgcnn).exit_code, 0);
  ASSERT_EQ(run(part(2, 3), scratch_ / "b", dgcnn).exit_code, 0);
  const auto r = merge(quoted((scratch_ / "a").string()) + " " + quoted((scratch_ / "b").string()) + " --out " +
                       quoted((scratch_ / "merged").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto unknown = [](const PointBuffer& points) {
    return std::count(points.labels().begin(), points.labels().end(), static_cast<std::uint8_t>(ClassId::Unknown));
  };
  const PointBuffer merged = read_point_cloud(scratch_ / "merged" / "semantic_points.ply");
  const PointBuffer whole = read_point_cloud(scratch_ / "whole" / "semantic_points.ply");
  ASSERT_GT(whole.size(), 100u);
  // The parts' blocks saw less than the whole run's, so a point the whole
  // run kept may have waited for its class in a part (and the reverse):
  // about the same points, and none lost its class in the merge.
  EXPECT_NEAR(static_cast<double>(merged.size()), static_cast<double>(whole.size()), 0.1 * whole.size());
  EXPECT_LE(unknown(merged), unknown(whole) + static_cast<long>(whole.size() / 100));
}

TEST_F(MergeCommand, ARunCarriedByATransformLandsWhereItSays) {
  RELEASE_ONLY();
  ASSERT_EQ(run(seq(), scratch_ / "a").exit_code, 0);
  fs::copy(scratch_ / "a", scratch_ / "far", fs::copy_options::recursive);
  // A quarter turn and 30 m away: the two maps do not meet.
  const auto r = merge(quoted((scratch_ / "a").string()) + " " + quoted((scratch_ / "far").string()) +
                       " --transform " + quoted((scratch_ / "far").string()) + "=30,-4,0,90 --out " +
                       quoted((scratch_ / "merged").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(known_voxels(scratch_ / "merged"), 2 * known_voxels(scratch_ / "a"));
  const auto segments = [&](const fs::path& run) { return json_of(run / "segments.json").at("segments").size(); };
  EXPECT_EQ(segments(scratch_ / "merged"), 2 * segments(scratch_ / "a"));
  const auto transform = json_of(scratch_ / "merged" / "manifest.json").at("input").at("runs").at(1).at("transform");
  EXPECT_EQ(transform.at("x"), 30.0);
  EXPECT_EQ(transform.at("yaw_deg"), 90.0);
  // Where the first run's map is, the merge holds the first run's map.
  const metric::MetricMap merged = metric::load_map(scratch_ / "merged" / "map.sarmap");
  const metric::MetricMap first = metric::load_map(scratch_ / "a" / "map.sarmap");
  for (const metric::BlockKey& k : first.blocks().sorted_block_keys()) {
    for (int l = 0; l < metric::kBlockVoxels; ++l) {
      const metric::VoxelKey key = metric::voxel_of(k, l);
      ASSERT_EQ(merged.state(key), first.state(key));
    }
  }
}

TEST_F(MergeCommand, RunsThatCannotMergeAndBadOptionsAreRefusedBeforeAnythingIsWritten) {
  ASSERT_EQ(run(seq(), scratch_ / "a").exit_code, 0);
  fs::copy(scratch_ / "a", scratch_ / "b", fs::copy_options::recursive);
  ASSERT_EQ(run(seq(), scratch_ / "plain", "--classifier labels --voxel 0.1").exit_code, 0);
  ASSERT_EQ(run(seq(), scratch_ / "coarse", "--keep-state --classifier labels --voxel 0.2").exit_code, 0);
  const std::string a = quoted((scratch_ / "a").string()), b = quoted((scratch_ / "b").string());
  const std::string out = " --out " + quoted((scratch_ / "out").string());
  const auto refused = [&](const std::string& args, const std::string& why) {
    const auto r = merge(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_NE(r.err.find(why), std::string::npos) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(scratch_ / "out" / "manifest.json")) << args;
  };
  refused(a + " " + quoted((scratch_ / "plain").string()) + out, "--keep-state");
  refused(a + " " + quoted((scratch_ / "coarse").string()) + out, "cannot merge maps with");  // 0.2 m into 0.1 m
  refused(a + out, "two or more runs");
  refused(a + " " + b + " --out " + a, "is one of the runs");
  refused(a + " " + b + out + " --transform " + b + "=1,2,3", "four finite numbers");
  refused(a + " " + b + out + " --transform " + b + "=1,2,nan,0", "four finite numbers");
  refused(a + " " + b + out + " --transform nowhere=1,2,3,0", "not one of the runs");
  refused(a + " " + b + out + " --transform " + b + "=1,2,3,0 --transform " + b + "=0,0,0,0", "two --transform");
  refused(a + " " + b + out + " --transform 1,2,3,0", "RUN=x,y,z,yaw_deg");
  refused(a + " " + quoted((scratch_ / "nowhere").string()) + out, "not a run folder");
  // A damaged state is named by the folder's own check.
  std::string bytes = read_all(scratch_ / "b" / "mapper.state");
  bytes[bytes.size() / 2] ^= 0x10;
  scratch_.write("b/mapper.state", bytes);
  refused(a + " " + b + out, "mapper.state");
}

}  // namespace
}  // namespace sarmap
