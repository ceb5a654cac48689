// The ray directions of a simulated sensor in its own frame, computed once.
// Depth camera (optical frame: x right, y down, z forward): the direction of
// pixel (u, v) is ((u - cx) / fx, (v - cy) / fy, 1), so a hit's ray parameter
// IS its depth. LiDAR (body frame: x forward, z up): unit vectors, parameter =
// range; rings evenly spaced over the vertical field of view, azimuth from +x
// counter-clockwise in horizontal_samples steps.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "engine/sim/arena.hpp"

namespace sarmap::sim {

struct SensorRays {
  int rows = 0;  // image rows or LiDAR rings
  int cols = 0;  // image columns or samples per ring
  std::vector<Eigen::Vector3f> directions;  // rows * cols, row-major, sensor frame
};

SensorRays make_sensor_rays(const SensorSpec& sensor);

}  // namespace sarmap::sim
