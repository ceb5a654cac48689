// One posed scan as it travels through the pipeline.
#pragma once

#include <cstddef>
#include <string>

#include <Eigen/Core>

#include "engine/core/point_buffer.hpp"
#include "engine/core/pose.hpp"

namespace sarmap {

struct Scan {
  // Points in the world frame (readers move sensor-frame points by the pose).
  PointBuffer points;
  // Sensor-to-world transform of this frame.
  Pose pose;
  // Where the rays start, in the world frame (usually the pose's translation).
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double timestamp = 0.0;
  // Position in its sequence, from 0.
  std::size_t index = 0;
  // File the points came from, for messages.
  std::string source;
  // Points dropped while reading because a coordinate was NaN or infinite.
  std::size_t dropped_non_finite = 0;
};

}  // namespace sarmap
