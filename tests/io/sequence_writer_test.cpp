#include "engine/io/sequence_writer.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/scan_source.hpp"
#include "error_message.hpp"
#include "scratch_folder.hpp"
#include "tests/file_bytes.hpp"

namespace sarmap {
namespace {

using test::error_message;
using ::testing::HasSubstr;

Scan make_scan(int i) {
  Scan scan;
  scan.pose = Pose::from_quaternion(0.1 * i, -0.2, 0.3, 0.9, Eigen::Vector3d(i, 2.0 * i, 0.5));
  scan.origin = scan.pose.translation() + Eigen::Vector3d(0, 0, 0.25);
  scan.timestamp = 0.1 * i;
  scan.points.enable_labels();
  for (int p = 0; p < 5 + i; ++p) {
    scan.points.push_back(0.5f * p, -0.25f * i, 1.0f + 0.125f * p);
    scan.points.labels()[scan.points.size() - 1] = static_cast<std::uint8_t>((p + i) % 6);
  }
  return scan;
}

TEST(SequenceWriter, RoundTripsPointsPosesOriginsTimestampsAndLabels) {
  test::ScratchFolder dir;
  SensorInfo sensor;
  sensor.type = SensorType::DepthCamera;
  sensor.max_range = 6.0;
  sensor.intrinsics = PinholeIntrinsics{64, 48, 50, 50, 31.5, 23.5};
  SequenceWriter writer(dir / "seq", sensor);
  for (int i = 0; i < 3; ++i) writer.add(make_scan(i));
  EXPECT_EQ(writer.frames_written(), 3u);
  // Until finish() no index names the frames.
  EXPECT_FALSE(std::filesystem::exists(dir / "seq/sequence.json"));
  writer.finish();
  EXPECT_TRUE(std::filesystem::exists(dir / "seq/frame_000002.ply"));

  auto source = open_scan_sequence(dir / "seq");
  EXPECT_EQ(source->layout(), "sarmap");
  ASSERT_EQ(source->size(), 3u);
  EXPECT_EQ(source->sensor().type, SensorType::DepthCamera);
  EXPECT_EQ(source->sensor().max_range, 6.0);
  ASSERT_TRUE(source->sensor().intrinsics);
  EXPECT_EQ(source->sensor().intrinsics->cx, 31.5);
  Scan scan;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(source->next(scan));
    const Scan expected = make_scan(i);
    EXPECT_EQ(scan.index, static_cast<std::size_t>(i));
    EXPECT_EQ(scan.pose.matrix(), expected.pose.matrix());
    EXPECT_EQ(scan.origin, expected.origin);
    EXPECT_EQ(scan.timestamp, expected.timestamp);
    ASSERT_EQ(scan.points.size(), expected.points.size());
    ASSERT_TRUE(scan.points.has_labels());
    for (std::size_t p = 0; p < scan.points.size(); ++p) {
      // World-frame points are stored as they are: not moved again by the pose.
      EXPECT_EQ(scan.points.x()[p], expected.points.x()[p]);
      EXPECT_EQ(scan.points.y()[p], expected.points.y()[p]);
      EXPECT_EQ(scan.points.z()[p], expected.points.z()[p]);
      EXPECT_EQ(scan.points.labels()[p], expected.points.labels()[p]);
    }
  }
  EXPECT_FALSE(source->next(scan));
}

TEST(SequenceWriter, ReplacesAnOldIndexAndRefusesBadInput) {
  test::ScratchFolder dir;
  {
    SequenceWriter first(dir.path(), SensorInfo{});
    first.add(make_scan(0));
    first.add(make_scan(1));
    first.finish();
  }
  SequenceWriter second(dir.path(), SensorInfo{});
  EXPECT_FALSE(std::filesystem::exists(dir / "sequence.json"));
  second.add(make_scan(2));
  Scan earlier = make_scan(1);
  EXPECT_THAT(error_message([&] { second.add(earlier); }), HasSubstr("earlier than the previous frame"));
  earlier.timestamp = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(error_message([&] { second.add(earlier); }), HasSubstr("must be finite"));
  second.finish();
  EXPECT_EQ(open_scan_sequence(dir.path())->size(), 1u);
  EXPECT_THAT(error_message([&] { second.add(make_scan(3)); }), HasSubstr("after finish"));

  SensorInfo no_size;
  no_size.type = SensorType::DepthCamera;
  no_size.intrinsics = PinholeIntrinsics{0, 0, 50, 50, 1, 1};
  EXPECT_THAT(error_message([&] { SequenceWriter(dir / "x", no_size); }), HasSubstr("width and height"));
  SensorInfo untyped;
  untyped.max_range = 4;
  EXPECT_THAT(error_message([&] { SequenceWriter(dir / "y", untyped); }), HasSubstr("needs a sensor type"));
  SensorInfo lidar_k;
  lidar_k.type = SensorType::Lidar;
  lidar_k.intrinsics = PinholeIntrinsics{4, 4, 50, 50, 1, 1};
  EXPECT_THAT(error_message([&] { SequenceWriter(dir / "z", lidar_k); }), HasSubstr("depth camera"));
}

// The arena hash a simulation records reaches the run through the source.
TEST(SequenceWriter, RecordsTheArenaHash) {
  test::ScratchFolder dir;
  const std::string hash = "0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef";
  {
    SequenceWriter writer(dir / "sim", SensorInfo{});
    writer.add(make_scan(0));
    writer.set_arena_sha256(hash);
    writer.finish();
    EXPECT_THAT(error_message([&] { writer.set_arena_sha256(hash); }), HasSubstr("after finish"));
  }
  EXPECT_EQ(open_scan_sequence(dir / "sim")->arena_sha256(), hash);
  {
    SequenceWriter writer(dir / "recorded", SensorInfo{});
    writer.add(make_scan(0));
    writer.finish();
  }
  EXPECT_EQ(open_scan_sequence(dir / "recorded")->arena_sha256(), "");
  SequenceWriter writer(dir / "bad", SensorInfo{});
  EXPECT_THAT(error_message([&] { writer.set_arena_sha256("abc"); }), HasSubstr("not 64 lowercase hex digits"));
}

// Only what the writer writes goes: sequence.json, frame_NNNNNN.ply (six or
// more digits) and the temporaries of writers that are gone; near-miss names,
// other files, subfolders, symlinks and a live writer's temporary stay.
TEST(SequenceWriter, RemoveWrittenSequenceRemovesOnlyTheWritersFiles) {
  namespace fs = std::filesystem;
  test::ScratchFolder dir;
  {
    SequenceWriter writer(dir.path(), SensorInfo{});
    for (int i = 0; i < 3; ++i) writer.add(make_scan(i));
    writer.finish();
  }
  dir.write("frame_1234567.ply", "frame 1,234,567");
  const pid_t gone = ::fork();
  if (gone == 0) ::_exit(0);
  ::waitpid(gone, nullptr, 0);
  const std::string dead = ".frame_000003.ply.tmp." + std::to_string(gone) + ".1";
  const std::string live = ".frame_000003.ply.tmp." + std::to_string(::getpid()) + ".2";
  dir.write(dead, "half a frame");
  dir.write(live, "being written");
  const std::vector<std::string> kept = {"notes.txt",        "frame_00001.ply",     "frame_000001.pcd",
                                         "frame_00000a.ply", "my_frame_000001.ply", "sub/frame_000000.ply",
                                         live};
  for (const std::string& name : kept) {
    if (!fs::exists(dir / name)) dir.write(name, "not the writer's");
  }
  fs::create_symlink(dir / "notes.txt", dir / "frame_000009.ply");

  remove_written_sequence(dir.path());
  std::vector<std::string> left;
  for (const auto& entry : fs::recursive_directory_iterator(dir.path())) {
    if (!entry.is_directory()) left.push_back(entry.path().lexically_relative(dir.path()).string());
  }
  std::vector<std::string> expected = kept;
  expected.push_back("frame_000009.ply");
  std::sort(left.begin(), left.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(left, expected);
  EXPECT_EQ(test::slurp(dir / "notes.txt"), "not the writer's");

  remove_written_sequence(dir / "absent");  // nothing to clear is no error
  EXPECT_FALSE(fs::exists(dir / "absent"));
}

}  // namespace
}  // namespace sarmap
