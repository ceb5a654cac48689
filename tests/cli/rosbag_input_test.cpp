// sarmap run BAG.bag against sarmap run FOLDER on the same frames: a bag that
// Debian's python3-rosbag writes (tests/cli/write_rosbag.py) from a simulated
// sequence gives a byte-identical map.sarmap whether its poses come from
// nav_msgs/Odometry, geometry_msgs/PoseStamped or /tf; and bad bags (a missing
// topic, no messages, truncated, a scan with no pose near it) are refused or
// skipped with an error that says what is wrong. Exits 77 (CTest: skipped)
// when python3-rosbag is missing; tools/install-deps.sh installs it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "engine/io/scan_source.hpp"
#include "engine/io/sequence_writer.hpp"
#include "tests/cli/cli_runner.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::read_all;
using test::run_cli;
using ::testing::HasSubstr;

const std::string kPython = SARMAP_ROSBAG_PYTHON;
const std::string kWriter = std::string(SARMAP_SOURCE_DIR) + "/tests/cli/write_rosbag.py";

class RosbagInput : public ::testing::Test {
 protected:
  // Simulates the tiny arena (3 frames, 64 x 48), then writes its frames twice
  // over: in the sensor frame with a quaternion pose for the bags, and placed
  // in the world by that same pose, as a sequence folder, so both inputs give
  // the scans the same float coordinates.
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("sarmap_rosbag_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_ / "frames");
    const auto r =
        run_cli("simulate " + quoted(std::string(SARMAP_SOURCE_DIR) + "/tests/cli/data/tiny_arena.json") +
                    " --out " + quoted((*dir_ / "simulated").string()) + " --quiet",
                *dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;

    const auto source = open_scan_sequence(*dir_ / "simulated");
    SequenceWriter folder(*dir_ / "sequence", SensorInfo{});
    std::ofstream list(*dir_ / "frames" / "frames.txt");
    list.precision(17);
    Scan scan;
    for (int i = 0; source->next(scan); ++i) {
      const Eigen::Quaterniond q(scan.pose.rotation());
      const Pose pose = Pose::from_quaternion(q.x(), q.y(), q.z(), q.w(), scan.pose.translation());
      const double stamp = 100.0 + scan.timestamp;  // ROS stamps of 0 mean "no stamp"
      // Sensor-frame points; the world-frame copy is that moved by `pose`, as the bag reader moves it.
      const Eigen::Matrix3d rt = pose.rotation().transpose();
      PointBuffer sensor = scan.points;
      for (std::size_t k = 0; k < sensor.size(); ++k) {
        const Eigen::Vector3d p =
            rt * (Eigen::Vector3d(scan.points.x()[k], scan.points.y()[k], scan.points.z()[k]) -
                  pose.translation());
        sensor.x()[k] = static_cast<float>(p.x());
        sensor.y()[k] = static_cast<float>(p.y());
        sensor.z()[k] = static_cast<float>(p.z());
      }
      std::ofstream bin(*dir_ / "frames" / ("frame_" + std::to_string(i) + ".bin"), std::ios::binary);
      for (std::size_t k = 0; k < sensor.size(); ++k) {
        const float xyz[3] = {sensor.x()[k], sensor.y()[k], sensor.z()[k]};
        bin.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
        bin.put(static_cast<char>(sensor.labels()[k]));
      }
      list << stamp << ' ' << pose.translation().x() << ' ' << pose.translation().y() << ' '
           << pose.translation().z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
      Scan placed;
      placed.points = sensor;
      pose.apply(placed.points);
      placed.pose = pose;
      placed.origin = pose.translation();
      placed.timestamp = stamp;
      folder.add(placed);
    }
    folder.finish();
    list.close();
    const auto reference = run("sequence", "sequence_run", "");
    ASSERT_EQ(reference.exit_code, 0) << reference.err;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }

  // Writes BAG with write_rosbag.py; `options` are the script's.
  static void write_bag(const std::string& bag, const std::string& options) {
    const std::string command = quoted(kPython) + " " + quoted(kWriter) + " " +
                                quoted((*dir_ / "frames").string()) + " " + quoted((*dir_ / bag).string()) +
                                " " + options;
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }
  static test::CliResult run(const std::string& input, const std::string& out, const std::string& options) {
    return run_cli("run " + quoted((*dir_ / input).string()) + " --out " + quoted((*dir_ / out).string()) +
                       " --voxel 0.1 --classifier labels --quiet " + options,
                   *dir_);
  }
  static std::string map_bytes(const std::string& out) { return read_all(*dir_ / out / "map.sarmap"); }

  static fs::path* dir_;
};
fs::path* RosbagInput::dir_ = nullptr;

TEST_F(RosbagInput, OdometryPosesGiveTheSameMapAsTheSequenceFolder) {
  write_bag("odometry.bag", "--pose odometry");
  const auto r = run("odometry.bag", "odometry_run", "");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  ASSERT_FALSE(map_bytes("sequence_run").empty());
  EXPECT_EQ(map_bytes("odometry_run"), map_bytes("sequence_run"));
  EXPECT_EQ(read_all(*dir_ / "odometry_run" / "voxels.ply"), read_all(*dir_ / "sequence_run" / "voxels.ply"));
  // info reads the bag as a sequence: its frames, and the NaN padding points dropped.
  const auto info = run_cli("info --json " + quoted((*dir_ / "odometry.bag").string()), *dir_);
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j.at("layout"), "rosbag");
  EXPECT_EQ(j.at("frames"), 3);
  EXPECT_GT(j.at("dropped_non_finite").get<int>(), 0);
}

TEST_F(RosbagInput, PoseStampedWithFloat64PointsAndTwoCloudTopics) {
  write_bag("pose.bag", "--pose pose_stamped --xyz64 --second-cloud-topic --compression bz2");
  const auto ambiguous = run("pose.bag", "pose_run", "");
  EXPECT_EQ(ambiguous.exit_code, 1);
  EXPECT_THAT(ambiguous.err, HasSubstr("more than one sensor_msgs/PointCloud2 topic"));
  EXPECT_THAT(ambiguous.err, HasSubstr("/points (sensor_msgs/PointCloud2)"));
  EXPECT_THAT(ambiguous.err, HasSubstr("/points_raw (sensor_msgs/PointCloud2)"));

  const auto r = run("pose.bag", "pose_run", "--cloud-topic /points --pose-topic /pose");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(map_bytes("pose_run"), map_bytes("sequence_run"));
}

TEST_F(RosbagInput, TfPosesFromAFixedFrame) {
  write_bag("tf.bag", "--pose tf --compression lz4");
  const auto r = run("tf.bag", "tf_run", "--fixed-frame map");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(map_bytes("tf_run"), map_bytes("sequence_run"));

  const auto no_frame = run("tf.bag", "tf_bad", "--fixed-frame world");
  EXPECT_EQ(no_frame.exit_code, 1);
  EXPECT_THAT(no_frame.err,
              HasSubstr("/tf has no frame 'world' (--fixed-frame); its frames: charger map sensor"));
  const auto no_pose_topic = run("tf.bag", "tf_bad", "");
  EXPECT_EQ(no_pose_topic.exit_code, 1);
  EXPECT_THAT(no_pose_topic.err,
              HasSubstr("no Odometry or PoseStamped topic: give --pose-topic, or --fixed-frame"));
}

TEST_F(RosbagInput, AScanWithNoPoseNearItIsSkippedWithAWarning) {
  write_bag("gap.bag", "--pose odometry --drop-pose 1");
  const auto r = run("gap.bag", "gap_run", "");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err,
              HasSubstr("/points message 1: no pose on /odom within 0.02 s of the cloud's stamp 101 s"));
  const auto profile = nlohmann::json::parse(read_all(*dir_ / "gap_run" / "profile.json"));
  EXPECT_EQ(profile.at("skipped_scans"), 1);
  EXPECT_EQ(profile.at("skipped").at(0).at("scan"), 1);
  // info describes the same bag, counting the scan it cannot place.
  const auto info = run_cli("info --json " + quoted((*dir_ / "gap.bag").string()), *dir_);
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j.at("frames"), 2);
  EXPECT_EQ(j.at("unreadable_frames"), 1);
  EXPECT_THAT(j.at("first_unreadable").get<std::string>(), HasSubstr("/points message 1: no pose on /odom"));
  // A wider tolerance takes the next frame's decoy pose, 0.6 s later, and nothing is skipped.
  const auto wide = run("gap.bag", "gap_wide", "--max-time-difference 0.7");
  ASSERT_EQ(wide.exit_code, 0) << wide.err;
  EXPECT_EQ(wide.err, "");
  // --strict makes the first such scan end the run.
  const auto strict = run("gap.bag", "gap_strict", "--strict");
  EXPECT_EQ(strict.exit_code, 1);
  EXPECT_THAT(strict.err, HasSubstr("no pose on /odom"));
}

TEST_F(RosbagInput, BadBagsAreRefusedNamingWhatIsWrong) {
  write_bag("empty.bag", "--empty");
  const auto empty = run("empty.bag", "bad_run", "");
  EXPECT_EQ(empty.exit_code, 1);
  EXPECT_THAT(empty.err, HasSubstr("empty.bag: no sensor_msgs/PointCloud2 topic; the bag has no topics"));

  write_bag("ok.bag", "--pose odometry");
  const auto missing = run("ok.bag", "bad_run", "--cloud-topic /velodyne_points");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_THAT(missing.err, HasSubstr("no topic /velodyne_points (--cloud-topic); the bag has: /odom "
                                     "(nav_msgs/Odometry) /points (sensor_msgs/PointCloud2)"));
  const auto wrong_type = run("ok.bag", "bad_run", "--pose-topic /points");
  EXPECT_EQ(wrong_type.exit_code, 1);
  EXPECT_THAT(wrong_type.err,
              HasSubstr("topic /points holds sensor_msgs/PointCloud2, not nav_msgs/Odometry"));

  // A message larger than --max-file-mb is refused before it is read.
  const auto too_big = run("ok.bag", "bad_run", "--max-file-mb 0.001");
  EXPECT_EQ(too_big.exit_code, 1);
  EXPECT_THAT(too_big.err, HasSubstr("/points message 0: "));
  EXPECT_THAT(too_big.err, HasSubstr("bytes, more than --max-file-mb allows"));

  const std::string bytes = read_all(*dir_ / "ok.bag");
  for (const std::size_t keep : {bytes.size() / 2, std::size_t{100}, std::size_t{5}}) {
    std::ofstream(*dir_ / "cut.bag", std::ios::binary)
        .write(bytes.data(), static_cast<std::streamsize>(keep));
    const auto cut = run("cut.bag", "bad_run", "");
    EXPECT_EQ(cut.exit_code, 1) << keep;
    EXPECT_THAT(cut.err, HasSubstr("cut.bag: not a readable ROS 1 bag")) << keep;
  }
  EXPECT_FALSE(fs::exists(*dir_ / "bad_run" / "manifest.json"));
  // Bag options on something that is not a bag are a mistake, said so.
  const auto not_bag = run("sequence", "bad_run", "--cloud-topic /points");
  EXPECT_EQ(not_bag.exit_code, 1);
  EXPECT_THAT(not_bag.err, HasSubstr("apply to ROS bags (.bag) only"));
}

}  // namespace
}  // namespace sarmap

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const std::string probe =
      "'" + std::string(SARMAP_ROSBAG_PYTHON) + "' -c 'import rosbag, genpy' 2>/dev/null";
  if (std::system(probe.c_str()) != 0) {
    std::printf("python3-rosbag is missing (%s): skipped; tools/install-deps.sh installs it\n",
                SARMAP_ROSBAG_PYTHON);
    return 77;
  }
  return RUN_ALL_TESTS();
}
