// A ROS 1 bag as a scan sequence: each sensor_msgs/PointCloud2 message on one
// topic is a scan, placed by the nearest pose in time from a nav_msgs/Odometry
// or geometry_msgs/PoseStamped topic, or from /tf (and /tf_static) between a
// fixed frame and the cloud's frame. The bag container is read by Debian's
// librosbag (rosbag_storage: uncompressed, bz2 and lz4 chunks); the messages
// by ros_messages.hpp. Options and rules: docs/formats.md, "ROS 1 bags".
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "engine/io/scan_source.hpp"

namespace sarmap {

struct RosbagOptions {
  // The PointCloud2 topic; may be empty when the bag has only one.
  std::string cloud_topic;
  // An Odometry or PoseStamped topic giving the cloud frame's pose in the world.
  std::string pose_topic;
  // With no pose topic: the world frame of /tf, in which the cloud's frame is looked up.
  std::string fixed_frame;
};

// A path ending in ".bag" (any case).
bool is_rosbag_path(const std::filesystem::path& path);

// Opens the bag and reads its poses (the clouds are read one by one by
// next()). A pose more than sequence_options.max_time_difference seconds from
// a cloud's header stamp makes next() throw sarmap::Error (InvalidData) for
// that scan, after moving past it. Throws sarmap::Error naming the bag for a
// file that is no bag or is damaged, a missing topic (listing the bag's
// topics with their types), a topic of the wrong type, or a pose source left
// ambiguous.
std::unique_ptr<ScanSource> open_rosbag_sequence(const std::filesystem::path& path,
                                                 const RosbagOptions& options,
                                                 const ScanSequenceOptions& sequence_options = {});

}  // namespace sarmap
