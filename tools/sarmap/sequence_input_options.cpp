#include "tools/sarmap/sequence_input_options.hpp"

#include <cctype>
#include <cstdint>

#include "engine/core/error.hpp"
#include "tools/sarmap/number_checks.hpp"
#ifdef SARMAP_HAVE_ROSBAG
#include "engine/io_rosbag/rosbag_sequence.hpp"
#endif

namespace sarmap::cli {

ScanSequenceOptions SequenceInputArgs::options() const {
  ScanSequenceOptions options;
  if (!intrinsics.empty()) options.intrinsics_file = intrinsics;
  options.max_time_difference = max_time_difference;
  // Past 2^64 bytes the cast would be undefined: any such limit means none.
  const double bytes = max_file_mb * 1024 * 1024;
  options.limits.max_file_bytes = bytes >= 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(bytes);
  options.limits.max_points = max_scan_points;
  return options;
}

void add_sequence_input_options(CLI::App* cmd, SequenceInputArgs& args) {
  cmd->add_option("--intrinsics", args.intrinsics,
                  "Depth-camera intrinsics for TUM / 7-Scenes: JSON {fx, fy, cx, cy} or a 3x3 matrix as text");
  cmd->add_option("--max-time-difference", args.max_time_difference,
                  "TUM and ROS bags: largest gap in seconds between a frame (a cloud's stamp) and the pose "
                  "taken for it")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--max-file-mb", args.max_file_mb,
                  "Refuse an input file (a frame, a cloud, a depth image) larger than this many MiB, before "
                  "reading it")
      ->capture_default_str()
      ->check(finite_positive());
  cmd->add_option("--max-scan-points", args.max_scan_points,
                  "Refuse a frame or cloud of more points (a header's count, a depth image's pixels), before "
                  "allocating for it")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--cloud-topic", args.cloud_topic,
                  "ROS bag: the sensor_msgs/PointCloud2 topic (needed only when the bag has more than one)");
  cmd->add_option("--pose-topic", args.pose_topic,
                  "ROS bag: the nav_msgs/Odometry or geometry_msgs/PoseStamped topic placing the clouds "
                  "(needed only when the bag has more than one)");
  cmd->add_option(
      "--fixed-frame", args.fixed_frame,
      "ROS bag: place the clouds by /tf and /tf_static, as their frame seen from this world frame "
      "(instead of a pose topic)");
}

bool is_bag_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".bag";
}

std::unique_ptr<ScanSource> open_input_sequence(const std::filesystem::path& path,
                                                const SequenceInputArgs& args) {
  const bool bag = is_bag_path(path);
  if (!bag && !(args.cloud_topic.empty() && args.pose_topic.empty() && args.fixed_frame.empty())) {
    throw Error(
        ErrorCode::InvalidArgument,
        path.string() + ": --cloud-topic, --pose-topic and --fixed-frame apply to ROS bags (.bag) only");
  }
  if (bag) {
#ifdef SARMAP_HAVE_ROSBAG
    RosbagOptions options;
    options.cloud_topic = args.cloud_topic;
    options.pose_topic = args.pose_topic;
    options.fixed_frame = args.fixed_frame;
    return open_rosbag_sequence(path, options, args.options());
#else
    throw Error(ErrorCode::Unsupported,
                path.string() +
                    ": this sarmap was built without ROS bag input (install librosbag-storage-dev "
                    "and configure again)");
#endif
  }
  return open_scan_sequence(path, args.options());
}

}  // namespace sarmap::cli
