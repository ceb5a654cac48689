// Links the installed sarmap library: builds a small cloud, moves it by a pose
// and prints its bounds.
#include <cstdio>

#include "engine/core/point_buffer.hpp"
#include "engine/core/pose.hpp"
#include "engine/core/version.hpp"

int main() {
  sarmap::PointBuffer points;
  points.push_back(0.f, 0.f, 0.f);
  points.push_back(1.f, 2.f, 3.f);
  const auto pose = sarmap::Pose::from_quaternion(0, 0, 0, 1, Eigen::Vector3d(1, 0, 0));
  pose.apply(points);
  const sarmap::Bounds b = points.bounds();
  std::printf("sarmap %s: %zu points, x in [%.1f, %.1f]\n", sarmap::kVersion, points.size(), b.min.x(), b.max.x());
  return b.min.x() == 1.0 ? 0 : 1;
}
