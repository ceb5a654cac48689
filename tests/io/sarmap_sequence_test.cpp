#include "engine/io/sarmap_sequence.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "error_message.hpp"
#include "scratch_folder.hpp"

namespace sarmap {
namespace {

using test::error_message;
using ::testing::HasSubstr;

PointBuffer sensor_points() {
  PointBuffer p;
  p.push_back(1, 0, 0);
  p.push_back(0, 2, 0);
  p.push_back(std::numeric_limits<float>::quiet_NaN(), 0, 0);
  p.push_back(0, 0, 3);
  return p;
}

// Frame 0 (PLY) has a 90-degree turn about z and a translation; frame 1 (PCD) the identity.
void write_sensor_frame_sequence(const test::ScratchFolder& dir) {
  write_point_cloud(dir / "a.ply", sensor_points());
  write_point_cloud(dir / "b.pcd", sensor_points());
  dir.write("sequence.json", R"({"version": 1, "points_frame": "sensor",
    "sensor": {"type": "lidar", "max_range": 20},
    "frames": [
      {"file": "a.ply", "pose": [0,-1,0,10, 1,0,0,20, 0,0,1,30, 0,0,0,1], "timestamp": 1.5},
      {"file": "b.pcd", "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "origin": [0, 0, 2], "timestamp": 2.5}]})");
}

TEST(SarmapSequence, SensorFramePointsAreMovedByTheirPose) {
  test::ScratchFolder dir;
  write_sensor_frame_sequence(dir);
  auto source = open_scan_sequence(dir / "sequence.json");  // the index file opens its folder
  EXPECT_EQ(source->layout(), "sarmap");
  EXPECT_EQ(source->sensor().type, SensorType::Lidar);
  EXPECT_EQ(source->sensor().max_range, 20.0);
  Scan scan;
  ASSERT_TRUE(source->next(scan));
  EXPECT_EQ(scan.dropped_non_finite, 1u);
  ASSERT_EQ(scan.points.size(), 3u);
  // R = turn about z: (x, y, z) -> (-y, x, z), then + (10, 20, 30).
  EXPECT_FLOAT_EQ(scan.points.x()[0], 10);
  EXPECT_FLOAT_EQ(scan.points.y()[0], 21);
  EXPECT_FLOAT_EQ(scan.points.x()[1], 8);
  EXPECT_FLOAT_EQ(scan.points.y()[1], 20);
  EXPECT_FLOAT_EQ(scan.points.z()[2], 33);
  EXPECT_TRUE(scan.origin.isApprox(Eigen::Vector3d(10, 20, 30)));
  EXPECT_EQ(scan.timestamp, 1.5);
  EXPECT_THAT(scan.source, HasSubstr("a.ply"));

  ASSERT_TRUE(source->next(scan));
  EXPECT_EQ(scan.index, 1u);
  EXPECT_TRUE(scan.origin.isApprox(Eigen::Vector3d(0, 0, 2)));
  EXPECT_FLOAT_EQ(scan.points.z()[2], 3);
  EXPECT_FALSE(source->next(scan));
}

TEST(SarmapSequence, MissingFramesAndBadLabelsAreNamed) {
  test::ScratchFolder dir;
  write_sensor_frame_sequence(dir);
  std::filesystem::remove(dir / "b.pcd");
  const std::string msg = error_message([&] { open_scan_sequence(dir.path()); });
  EXPECT_THAT(msg, HasSubstr("sequence.json: frames[1].file"));
  EXPECT_THAT(msg, HasSubstr("b.pcd does not exist"));

  PointBuffer labelled = sensor_points();
  labelled.enable_labels();
  labelled.labels()[1] = 9;
  write_point_cloud(dir / "b.pcd", labelled);
  auto source = open_scan_sequence(dir.path());
  Scan scan;
  ASSERT_TRUE(source->next(scan));
  EXPECT_THAT(error_message([&] { source->next(scan); }),
              HasSubstr("b.pcd: point 1: label 9 is not a class id"));

  dir.write("sequence.json", R"({"version": 2, "points_frame": "world", "frames": []})");
  EXPECT_THAT(error_message([&] { open_scan_sequence(dir.path()); }),
              HasSubstr("unsupported sequence version 2"));
  dir.write("sequence.json", R"({"version": 1, "points_frame": "world", "frames": [], "extra": 0})");
  EXPECT_THAT(error_message([&] { open_scan_sequence(dir.path()); }), HasSubstr("unknown key \"extra\""));
}

// Found by fuzz/sarmap_sequence_fuzz: a frame name longer than NAME_MAX made
// std::filesystem throw filesystem_error, which reached the user as an
// internal error.
TEST(SarmapSequence, AFrameNameTheSystemRefusesIsNamed) {
  test::ScratchFolder dir;
  write_sensor_frame_sequence(dir);
  const std::string long_name(300, 'f');
  dir.write("sequence.json", R"({"version": 1, "points_frame": "world", "frames": [
      {"file": ")" + long_name + R"(.ply", "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}]})");
  const std::string msg = error_message([&] { open_scan_sequence(dir.path()); });
  EXPECT_THAT(msg, HasSubstr("sequence.json: frames[0].file: "));
  EXPECT_THAT(msg, HasSubstr("File name too long"));
}

TEST(SingleCloudSource, AFileIsOneScanWithIdentityPose) {
  test::ScratchFolder dir;
  write_point_cloud(dir / "c.ply", sensor_points());
  auto source = open_scan_sequence(dir / "c.ply");
  EXPECT_EQ(source->layout(), "cloud");
  EXPECT_EQ(source->size(), 1u);
  Scan scan;
  ASSERT_TRUE(source->next(scan));
  EXPECT_EQ(scan.points.size(), 3u);
  EXPECT_EQ(scan.dropped_non_finite, 1u);
  EXPECT_EQ(scan.pose.matrix(), Eigen::Matrix4d::Identity());
  EXPECT_FALSE(source->next(scan));
  source->rewind();
  EXPECT_TRUE(source->next(scan));
  dir.write("c.xyz", "1 2 3\n");
  EXPECT_THAT(error_message([&] { open_scan_sequence(dir / "c.xyz"); }), HasSubstr("c.xyz"));
}

}  // namespace
}  // namespace sarmap
