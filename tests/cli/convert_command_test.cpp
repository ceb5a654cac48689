// `sarmap convert`: PLY <-> PCD round trips, ASCII output, sequences merged
// into one cloud or rewritten as a sarmap sequence, --voxel thinning.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <cmath>
#include <set>
#include <string>
#include <tuple>

#include "engine/io/point_cloud_file.hpp"
#include "engine/io/scan_source.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/io/scratch_folder.hpp"

namespace sarmap {
namespace {

using test::quoted;
using test::run_cli;
using ::testing::HasSubstr;

const std::string kTiny = std::string(SARMAP_TEST_DATA_DIR) + "/sequences/tiny";

PointBuffer sample_cloud() {
  PointBuffer points;
  points.enable_labels();
  points.enable_colors();
  for (int i = 0; i < 50; ++i) {
    points.push_back(0.37f * i, std::sin(0.1f * i), -0.01f * i * i);
    points.labels()[i] = static_cast<std::uint8_t>(i % 6);
    points.red()[i] = static_cast<std::uint8_t>(5 * i);
  }
  return points;
}

void expect_same_points(const PointBuffer& a, const PointBuffer& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.has_labels(), b.has_labels());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.x()[i], b.x()[i]);
    EXPECT_EQ(a.y()[i], b.y()[i]);
    EXPECT_EQ(a.z()[i], b.z()[i]);
    if (a.has_labels()) {
      EXPECT_EQ(a.labels()[i], b.labels()[i]);
    }
  }
}

TEST(CliConvert, PlyToPcdToPlyKeepsEveryPoint) {
  test::ScratchFolder dir;
  const PointBuffer original = sample_cloud();
  write_point_cloud(dir / "a.ply", original);
  auto r =
      run_cli("convert --quiet " + quoted((dir / "a.ply").string()) + " " + quoted((dir / "b.pcd").string()),
              dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("convert " + quoted((dir / "b.pcd").string()) + " " + quoted((dir / "c.ply").string()),
              dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("50 points"));
  PointCloudFileInfo info;
  const PointBuffer back = read_point_cloud(dir / "c.ply", &info);
  expect_same_points(original, back);
  EXPECT_TRUE(back.has_colors());
  EXPECT_EQ(back.red()[7], 35);
  EXPECT_EQ(info.encoding, "binary_little_endian");
}

TEST(CliConvert, AsciiOutputIsAscii) {
  test::ScratchFolder dir;
  write_point_cloud(dir / "a.ply", sample_cloud());
  const auto r = run_cli(
      "convert --ascii --quiet " + quoted((dir / "a.ply").string()) + " " + quoted((dir / "a.pcd").string()),
      dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(test::read_all(dir / "a.pcd"), HasSubstr("\nDATA ascii\n"));
  expect_same_points(sample_cloud(), read_point_cloud(dir / "a.pcd"));
}

TEST(CliConvert, SequenceMergesIntoOneWorldFrameCloud) {
  test::ScratchFolder dir;
  const auto r =
      run_cli("convert " + quoted(kTiny) + " " + quoted((dir / "merged.ply").string()), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // no progress line when stderr is not a terminal
  EXPECT_THAT(r.out, HasSubstr("5 points from 2 frames"));
  // Reference: the frames as the reader delivers them, appended.
  PointBuffer expected;
  auto source = open_scan_sequence(kTiny);
  Scan scan;
  while (source->next(scan)) expected.append(scan.points);
  expect_same_points(expected, read_point_cloud(dir / "merged.ply"));
  EXPECT_FLOAT_EQ(expected.x()[4], 2.5f);  // second frame: turned and moved
}

TEST(CliConvert, SequenceToSequenceFolder) {
  test::ScratchFolder dir;
  const auto r =
      run_cli("convert --quiet " + quoted(kTiny) + " " + quoted((dir / "copy").string()), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto a = open_scan_sequence(kTiny);
  auto b = open_scan_sequence(dir / "copy");
  ASSERT_EQ(a->size(), b->size());
  EXPECT_EQ(b->sensor().type, SensorType::Lidar);
  Scan sa, sb;
  while (a->next(sa)) {
    ASSERT_TRUE(b->next(sb));
    expect_same_points(sa.points, sb.points);
    EXPECT_EQ(sa.pose.matrix(), sb.pose.matrix());
    EXPECT_EQ(sa.timestamp, sb.timestamp);
  }
  EXPECT_EQ(b->arena_sha256(), "");  // a sequence that names no arena gives none
}

// A simulated sequence's arena stays named through convert, so its runs can
// still be checked against the arena by eval.
TEST(CliConvert, SequenceFolderKeepsTheArenaHash) {
  test::ScratchFolder dir;
  std::filesystem::copy(kTiny, dir / "sim");
  const std::string hash(64, 'c');
  std::string index = test::read_all(dir / "sim" / "sequence.json");
  index.replace(index.find("\"points_frame\""), 0, "\"arena_sha256\": \"" + hash + "\",\n ");
  std::filesystem::remove(dir / "sim" / "sequence.json");
  dir.write("sim/sequence.json", index);
  ASSERT_EQ(open_scan_sequence(dir / "sim")->arena_sha256(), hash);
  const auto r = run_cli("convert --quiet --voxel 0.5 " + quoted((dir / "sim").string()) + " " +
                             quoted((dir / "thinned").string()),
                         dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(open_scan_sequence(dir / "thinned")->arena_sha256(), hash);
}

TEST(CliConvert, VoxelKeepsTheFirstPointOfEachVoxel) {
  test::ScratchFolder dir;
  PointBuffer cloud;
  for (int i = 0; i < 400; ++i) {
    cloud.push_back(0.013f * (i % 37) - 0.2f, 0.021f * (i % 11), -0.007f * (i % 23));
  }
  write_point_cloud(dir / "dense.ply", cloud);
  const double size = 0.05;
  const auto r = run_cli("convert --quiet --voxel 0.05 " + quoted((dir / "dense.ply").string()) + " " +
                             quoted((dir / "thin.ply").string()),
                         dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Plain reference: walk the points in order, keep each one whose voxel is new.
  std::set<std::tuple<long, long, long>> seen;
  PointBuffer expected;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto key = std::make_tuple(std::lround(std::floor(cloud.x()[i] / size)),
                                     std::lround(std::floor(cloud.y()[i] / size)),
                                     std::lround(std::floor(cloud.z()[i] / size)));
    if (seen.insert(key).second) expected.push_back(cloud.x()[i], cloud.y()[i], cloud.z()[i]);
  }
  ASSERT_LT(expected.size(), cloud.size());
  expect_same_points(expected, read_point_cloud(dir / "thin.ply"));

  const auto bad = run_cli(
      "convert --voxel -1 " + quoted((dir / "dense.ply").string()) + " " + quoted((dir / "x.ply").string()),
      dir.path());
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_THAT(bad.err, HasSubstr("--voxel: must be a finite number > 0, got '-1'"));
}

TEST(CliConvert, ErrorsExitNonZeroWithAMessage) {
  test::ScratchFolder dir;
  write_point_cloud(dir / "a.ply", sample_cloud());
  auto r = run_cli("convert " + quoted((dir / "a.ply").string()) + " " + quoted((dir / "a.xyz").string()),
                   dir.path());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("a.xyz"));
  EXPECT_FALSE(std::filesystem::exists(dir / "a.xyz"));
  r = run_cli("convert " + quoted((dir / "none").string()) + " " + quoted((dir / "b.ply").string()),
              dir.path());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("sarmap: error: "));
  r = run_cli("convert " + quoted((dir / "a.ply").string()), dir.path());  // OUT missing
  EXPECT_NE(r.exit_code, 0);
}

}  // namespace
}  // namespace sarmap
