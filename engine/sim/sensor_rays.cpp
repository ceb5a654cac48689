#include "engine/sim/sensor_rays.hpp"

#include <cmath>
#include <numbers>

#include "engine/core/degrees.hpp"

namespace sarmap::sim {

SensorRays make_sensor_rays(const SensorSpec& sensor) {
  SensorRays rays;
  if (sensor.type == SensorType::Lidar) {
    rays.rows = sensor.rings;
    rays.cols = sensor.horizontal_samples;
    rays.directions.reserve(static_cast<std::size_t>(rays.rows) * static_cast<std::size_t>(rays.cols));
    for (int r = 0; r < rays.rows; ++r) {
      const double elevation =
          rays.rows == 1 ? 0.5 * (sensor.vertical_fov_min_deg + sensor.vertical_fov_max_deg) * kDeg
                         : (sensor.vertical_fov_min_deg +
                            (sensor.vertical_fov_max_deg - sensor.vertical_fov_min_deg) * r / (rays.rows - 1)) *
                               kDeg;
      for (int c = 0; c < rays.cols; ++c) {
        const double azimuth = 2.0 * std::numbers::pi * c / rays.cols;
        rays.directions.emplace_back(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                                     std::sin(elevation));
      }
    }
    return rays;
  }
  const PinholeIntrinsics& k = sensor.intrinsics;
  rays.rows = k.height;
  rays.cols = k.width;
  rays.directions.reserve(static_cast<std::size_t>(rays.rows) * static_cast<std::size_t>(rays.cols));
  for (int v = 0; v < rays.rows; ++v) {
    for (int u = 0; u < rays.cols; ++u) {
      rays.directions.emplace_back(static_cast<float>((u - k.cx) / k.fx), static_cast<float>((v - k.cy) / k.fy), 1.0f);
    }
  }
  return rays;
}

}  // namespace sarmap::sim
