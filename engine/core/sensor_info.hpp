// What a scan sequence says about the sensor that produced it.
#pragma once

#include <optional>
#include <string_view>

namespace sarmap {

enum class SensorType { Unknown, DepthCamera, Lidar };

std::string_view to_string(SensorType type);

// Pinhole intrinsics of a depth camera (pixels).
struct PinholeIntrinsics {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

struct SensorInfo {
  SensorType type = SensorType::Unknown;
  double min_range = 0.0;
  // 0 means not given; the mapper then uses its own setting.
  double max_range = 0.0;
  std::optional<PinholeIntrinsics> intrinsics;
};

}  // namespace sarmap
