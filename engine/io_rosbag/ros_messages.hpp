// The few ROS 1 messages a bag's scans and poses come in, decoded from their
// serialised bytes (little-endian; strings and arrays led by a u32 length):
// sensor_msgs/PointCloud2, nav_msgs/Odometry, geometry_msgs/PoseStamped and
// tf2_msgs/TFMessage. Decoded here rather than through the generated ROS
// message headers, which Debian ships in packages of their own, so that only
// the bag container needs librosbag and every bound is checked with an error
// that names the message and byte offset. No ROS header is included.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/core/point_buffer.hpp"
#include "engine/io/input_limits.hpp"

namespace sarmap::ros1 {

struct MessageHeader {
  double stamp = 0.0;  // seconds
  std::string frame_id;
};

// A rigid transform as ROS sends it: translation and quaternion (x, y, z, w).
struct RosTransform {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double qx = 0, qy = 0, qz = 0, qw = 1;
};

// The pose of child_frame_id in header.frame_id (PoseStamped has no child
// frame: empty), or one /tf edge.
struct StampedTransform {
  MessageHeader header;
  std::string child_frame_id;
  RosTransform transform;
};

struct CloudMessage {
  MessageHeader header;
  PointBuffer points;  // sensor frame; labels when the cloud has a label or class field
  std::size_t dropped_non_finite = 0;
};

// Each decoder throws sarmap::Error (Parse) naming `what` (the bag, topic and
// message number) and the byte offset when the bytes are not that message,
// (Unsupported) for a big-endian cloud or x/y/z that are not float32 or
// float64, (InvalidData) for a label that is no class id, and (OutOfRange)
// when the cloud has more points than limits.max_points. Points with a NaN
// or infinite coordinate are dropped and counted.
CloudMessage decode_point_cloud2(std::span<const std::uint8_t> bytes, const std::string& what,
                                 const InputLimits& limits = {});
StampedTransform decode_odometry(std::span<const std::uint8_t> bytes, const std::string& what);
StampedTransform decode_pose_stamped(std::span<const std::uint8_t> bytes, const std::string& what);
std::vector<StampedTransform> decode_tf_message(std::span<const std::uint8_t> bytes, const std::string& what);

}  // namespace sarmap::ros1
