#include "engine/io/sarmap_sequence_manifest.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <string>

#include "engine/core/error.hpp"
#include "error_message.hpp"

namespace sarmap {
namespace {

using test::error_message;
using ::testing::HasSubstr;

const std::string kIdentity = "[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]";
const std::string kTurnZ = "[0,-1,0,4, 1,0,0,5, 0,0,1,6, 0,0,0,1]";

std::string manifest_with(const std::string& frames, const std::string& extra = "") {
  return R"({"version": 1, "points_frame": "sensor", )" + extra + R"("frames": [)" + frames + "]}";
}

TEST(SequenceManifest, ParsesFramesWithDefaults) {
  const std::string text = R"({"version": 1, "points_frame": "sensor",
    "sensor": {"type": "depth_camera", "max_range": 8, "min_range": 0.3,
               "width": 64, "height": 48, "fx": 50, "fy": 51, "cx": 31.5, "cy": 23.5},
    "frames": [
      {"file": "a.ply", "pose": )" +
                           kTurnZ + R"(, "origin": [4, 5, 7]},
      {"file": "sub/b.PCD", "pose": )" +
                           kIdentity + R"(}]})";
  const SequenceManifest m = parse_sequence_manifest(text, "seq/sequence.json");
  EXPECT_EQ(m.points_frame, PointsFrame::Sensor);
  EXPECT_EQ(m.sensor.type, SensorType::DepthCamera);
  EXPECT_EQ(m.sensor.max_range, 8.0);
  EXPECT_EQ(m.sensor.min_range, 0.3);
  ASSERT_TRUE(m.sensor.intrinsics);
  EXPECT_EQ(m.sensor.intrinsics->width, 64);
  EXPECT_EQ(m.sensor.intrinsics->fy, 51.0);
  ASSERT_EQ(m.frames.size(), 2u);
  EXPECT_EQ(m.frames[0].file, "a.ply");
  EXPECT_TRUE(m.frames[0].pose.translation().isApprox(Eigen::Vector3d(4, 5, 6)));
  EXPECT_TRUE(m.frames[0].origin.isApprox(Eigen::Vector3d(4, 5, 7)));
  EXPECT_EQ(m.frames[1].file, "sub/b.PCD");
  EXPECT_TRUE(m.frames[1].origin.isZero());  // the pose's translation
  EXPECT_EQ(m.frames[1].timestamp, 0.0);
  EXPECT_EQ(parse_sequence_manifest(manifest_with(""), "s.json").sensor.type, SensorType::Unknown);
}

TEST(SequenceManifest, WrittenTextReadsBackIdentically) {
  SequenceManifest m;
  m.points_frame = PointsFrame::World;
  m.sensor.type = SensorType::Lidar;
  m.sensor.max_range = 30.25;
  m.sensor.min_range = 0.1;
  for (int i = 0; i < 3; ++i) {
    SequenceManifestFrame f;
    f.file = "frame_00000" + std::to_string(i) + ".ply";
    f.pose = Pose::from_quaternion(0.1 * i, 0.2, -0.3, 0.9, Eigen::Vector3d(i, -i * 0.1, 1.0 / 3.0));
    f.origin = f.pose.translation() + Eigen::Vector3d(0, 0, 0.1);
    f.timestamp = 1.0 / 7.0 * i;
    m.frames.push_back(f);
  }
  const SequenceManifest back = parse_sequence_manifest(sequence_manifest_json(m), "written");
  EXPECT_EQ(back.points_frame, PointsFrame::World);
  EXPECT_EQ(back.sensor.type, SensorType::Lidar);
  EXPECT_EQ(back.sensor.max_range, 30.25);
  EXPECT_EQ(back.sensor.min_range, 0.1);
  EXPECT_FALSE(back.sensor.intrinsics);
  ASSERT_EQ(back.frames.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back.frames[i].file, m.frames[i].file);
    EXPECT_EQ(back.frames[i].pose.matrix(), m.frames[i].pose.matrix());  // exact: full precision
    EXPECT_EQ(back.frames[i].origin, m.frames[i].origin);
    EXPECT_EQ(back.frames[i].timestamp, m.frames[i].timestamp);
  }
}

TEST(SequenceManifest, EveryBadFieldIsNamed) {
  auto msg = [](const std::string& text) {
    return error_message([&] { parse_sequence_manifest(text, "seq/sequence.json"); });
  };
  const std::string good = R"({"file": "f.ply", "pose": )" + kIdentity + "}";
  std::string frames =
      good + "," + good + "," + good + R"(, {"file": "f.ply", "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0]})";
  EXPECT_EQ(msg(manifest_with(frames)), "seq/sequence.json: frames[3].pose: expected 16 numbers, got 12");

  EXPECT_THAT(msg(R"({"version": 2, "points_frame": "world", "frames": []})"),
              HasSubstr("seq/sequence.json: version: unsupported sequence version 2"));
  EXPECT_THAT(msg(R"({"version": "1", "points_frame": "world", "frames": []})"), HasSubstr("version"));
  EXPECT_THAT(msg(R"({"points_frame": "world", "frames": []})"), HasSubstr("missing key \"version\""));
  EXPECT_THAT(msg(R"({"version": 1, "points_frame": "world", "frames": [], "colour": 1})"),
              HasSubstr("unknown key \"colour\""));
  EXPECT_THAT(msg(R"({"version": 1, "points_frame": "camera", "frames": []})"),
              HasSubstr("points_frame: expected \"world\" or \"sensor\", got \"camera\""));
  EXPECT_THAT(msg(R"({"version": 1, "points_frame": "world", "frames": {}})"),
              HasSubstr("frames: expected an array"));
  EXPECT_THAT(msg(R"({"version": 1, "points_frame": "world", "frames": [)"), HasSubstr("invalid JSON"));
  EXPECT_THAT(msg("[1, 2]"), HasSubstr("expected a JSON object"));

  EXPECT_THAT(msg(manifest_with(R"({"file": "f.ply", "pose": )" + kIdentity + R"(, "stamp": 1})")),
              HasSubstr("frames[0]: unknown key \"stamp\""));
  EXPECT_THAT(msg(manifest_with(R"({"pose": )" + kIdentity + "}")),
              HasSubstr("frames[0]: missing key \"file\""));
  EXPECT_THAT(msg(manifest_with(R"({"file": "f.txt", "pose": )" + kIdentity + "}")),
              HasSubstr("frames[0].file: \"f.txt\" is not a .ply or .pcd file"));
  EXPECT_THAT(msg(manifest_with(R"({"file": 3, "pose": )" + kIdentity + "}")), HasSubstr("frames[0].file"));
  EXPECT_THAT(msg(manifest_with(R"({"file": "/etc/f.ply", "pose": )" + kIdentity + "}")),
              HasSubstr("frames[0].file: \"/etc/f.ply\" leaves the sequence's folder"));
  EXPECT_THAT(msg(manifest_with(R"({"file": "../other/f.ply", "pose": )" + kIdentity + "}")),
              HasSubstr("frames[0].file: \"../other/f.ply\" leaves the sequence's folder"));
  // A subfolder is fine.
  EXPECT_NO_THROW(parse_sequence_manifest(manifest_with(R"({"file": "sub/f.ply", "pose": )" + kIdentity + "}"),
                                          "seq/sequence.json"));
  EXPECT_THAT(msg(manifest_with(R"({"file": "f.ply", "pose": [1,0,0,0, 0,1,0,0, 0,0,1,"x", 0,0,0,1]})")),
              HasSubstr("frames[0].pose[11]: expected a number, got string"));
  EXPECT_THAT(msg(manifest_with(R"({"file": "f.ply", "pose": [2,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]})")),
              HasSubstr("frames[0].pose: rotation is not orthonormal"));
  EXPECT_THAT(msg(manifest_with(R"({"file": "f.ply", "pose": [1,0,0,0, 0,1,0,0, 0,0,1,1e999, 0,0,0,1]})")),
              HasSubstr("number overflow"));  // JSON has no NaN / Inf; the parser refuses overflow
  EXPECT_THAT(msg(manifest_with(R"({"file": "f.ply", "pose": )" + kIdentity + R"(, "origin": [1, 2]})")),
              HasSubstr("frames[0].origin: expected 3 numbers, got 2"));
  EXPECT_THAT(msg(manifest_with(R"({"file": "f.ply", "pose": )" + kIdentity + R"(, "timestamp": null})")),
              HasSubstr("frames[0].timestamp: expected a number, got null"));
  EXPECT_THAT(msg(manifest_with(R"({"file": "a.ply", "pose": )" + kIdentity + R"(, "timestamp": 2},)" +
                                R"({"file": "b.ply", "pose": )" + kIdentity + R"(, "timestamp": 1})")),
              HasSubstr("frames[1].timestamp: 1 is earlier than frames[0].timestamp 2"));
  EXPECT_THAT(msg(manifest_with(R"({"file": "a.ply", "pose": )" + kIdentity + R"(, "timestamp": 2},)" +
                                R"({"file": "b.ply", "pose": )" + kIdentity + "}")),
              HasSubstr("frames[1]: timestamp given for some frames but not others"));

  EXPECT_THAT(msg(manifest_with("", R"("sensor": {"type": "sonar", "max_range": 1}, )")),
              HasSubstr("sensor.type: expected \"depth_camera\" or \"lidar\""));
  EXPECT_THAT(msg(manifest_with("", R"("sensor": {"type": "lidar"}, )")),
              HasSubstr("sensor: missing key \"max_range\""));
  EXPECT_THAT(msg(manifest_with("", R"("sensor": {"type": "lidar", "max_range": -1}, )")),
              HasSubstr("sensor.max_range: must not be negative"));
  EXPECT_THAT(msg(manifest_with("", R"("sensor": {"type": "lidar", "max_range": 5, "min_range": 6}, )")),
              HasSubstr("sensor.min_range: must be smaller"));
  EXPECT_THAT(msg(manifest_with("", R"("sensor": {"type": "lidar", "max_range": 5, "fov": 6}, )")),
              HasSubstr("sensor: unknown key \"fov\""));
  EXPECT_THAT(msg(manifest_with("", R"("sensor": {"type": "depth_camera", "max_range": 5, "fx": 6}, )")),
              HasSubstr("intrinsics need all of width, height, fx, fy, cx, cy"));
  EXPECT_THAT(msg(manifest_with("", R"("sensor": {"type": "depth_camera", "max_range": 5, "width": 0,
                                     "height": 4, "fx": 1, "fy": 1, "cx": 0, "cy": 0}, )")),
              HasSubstr("sensor.width: expected a positive whole number"));
}

// Simulated sequences name their arena by its hash; recordings and sequences
// written before the field existed have none and still read.
TEST(SequenceManifest, ArenaHashIsOptionalAndChecked) {
  const std::string hash(64, 'a');
  const std::string frame = R"({"file": "f.ply", "pose": )" + kIdentity + "}";
  EXPECT_EQ(parse_sequence_manifest(manifest_with(frame), "s.json").arena_sha256, "");
  const SequenceManifest with =
      parse_sequence_manifest(manifest_with(frame, R"("arena_sha256": ")" + hash + R"(", )"), "s.json");
  EXPECT_EQ(with.arena_sha256, hash);
  ASSERT_EQ(with.frames.size(), 1u);
  EXPECT_EQ(parse_sequence_manifest(sequence_manifest_json(with), "written").arena_sha256, hash);
  SequenceManifest without = with;
  without.arena_sha256.clear();
  const std::string text = sequence_manifest_json(without);
  EXPECT_EQ(text.find("arena_sha256"), std::string::npos) << text;
  EXPECT_EQ(parse_sequence_manifest(text, "written").arena_sha256, "");

  auto msg = [&](const std::string& value) {
    return error_message(
        [&] { parse_sequence_manifest(manifest_with(frame, R"("arena_sha256": )" + value + ", "), "s.json"); });
  };
  EXPECT_THAT(msg("\"" + std::string(64, 'A') + "\""), HasSubstr("s.json: arena_sha256: expected 64 lowercase hex"));
  EXPECT_THAT(msg("\"" + std::string(63, 'a') + "\""), HasSubstr("arena_sha256"));
  EXPECT_THAT(msg("\"" + std::string(63, 'a') + "g\""), HasSubstr("arena_sha256"));
  EXPECT_THAT(msg("12"), HasSubstr("arena_sha256"));
  EXPECT_THAT(msg("null"), HasSubstr("arena_sha256"));
}

}  // namespace
}  // namespace sarmap
