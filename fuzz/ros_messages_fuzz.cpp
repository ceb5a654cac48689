// libFuzzer target: the ROS 1 message decoders of bag input
// (engine/io_rosbag/ros_messages.hpp). The bag container is librosbag's and
// is not fuzzed here; these decoders are sarmap's own. The first byte picks
// the message type (PointCloud2, Odometry, PoseStamped, TFMessage), the rest
// is the serialised message, from memory.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io_rosbag/ros_messages.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::span<const std::uint8_t> message(data + 1, size - 1);
  const std::string what = "fuzz message";
  try {
    switch (data[0] % 4) {
      case 0: {
        sarmap::InputLimits limits;
        limits.max_points = 1 << 16;  // as --max-scan-points: a huge declared cloud is refused, not allocated
        (void)sarmap::ros1::decode_point_cloud2(message, what, limits);
        break;
      }
      case 1:
        (void)sarmap::ros1::decode_odometry(message, what);
        break;
      case 2:
        (void)sarmap::ros1::decode_pose_stamped(message, what);
        break;
      default:
        (void)sarmap::ros1::decode_tf_message(message, what);
        break;
    }
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
  }
  return 0;
}
