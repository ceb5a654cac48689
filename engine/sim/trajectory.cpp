#include "engine/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "engine/sim/ground_height.hpp"

namespace sarmap::sim {

Eigen::Matrix3d body_rotation(double yaw, double pitch_deg) {
  // A positive rotation about y turns x towards -z, so nose-down (negative
  // pitch) is a positive angle about y.
  const double pitch = -pitch_deg * std::numbers::pi / 180.0;
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
      .toRotationMatrix();
}

Eigen::Matrix3d optical_to_body() {
  Eigen::Matrix3d m;
  m << 0, 0, 1,  //
      -1, 0, 0,  //
      0, -1, 0;
  return m;
}

std::vector<Pose> trajectory_poses(const Arena& arena, const geometry::TriangleScene& scene) {
  const TrajectorySpec& t = arena.trajectory;
  if (!t.poses.empty()) return t.poses;
  const auto& w = t.waypoints;
  std::vector<double> cumulative{0.0};
  for (std::size_t i = 1; i < w.size(); ++i) cumulative.push_back(cumulative.back() + (w[i] - w[i - 1]).norm());
  const double total = cumulative.back();
  const Eigen::Matrix3d mount =
      arena.sensor.type == SensorType::DepthCamera ? optical_to_body() : Eigen::Matrix3d::Identity();
  std::vector<Pose> poses;
  poses.reserve(t.frames);
  std::size_t segment = 0;
  for (std::size_t f = 0; f < t.frames; ++f) {
    const double s = t.frames == 1 ? 0.0 : total * static_cast<double>(f) / static_cast<double>(t.frames - 1);
    // The segment holding s; a pose on a waypoint looks along the next segment.
    while (segment + 2 < w.size() && (s >= cumulative[segment + 1] || cumulative[segment + 1] == cumulative[segment])) {
      ++segment;
    }
    Eigen::Vector2d a = w[segment], b = w[segment + 1];
    const double seg_len = cumulative[segment + 1] - cumulative[segment];
    const double alpha = seg_len > 0 ? std::clamp((s - cumulative[segment]) / seg_len, 0.0, 1.0) : 0.0;
    // A zero-length last segment borrows the direction of the one before.
    Eigen::Vector2d dir = b - a;
    for (std::size_t k = segment; dir.norm() < 1e-12 && k > 0; --k) dir = w[k] - w[k - 1];
    const Eigen::Vector2d xy = a + alpha * (b - a);
    const double ground = ground_height(scene, xy.x(), xy.y(), arena.bounds_max.z());
    const Eigen::Vector3d position(xy.x(), xy.y(), ground + t.height);
    const double yaw = std::atan2(dir.y(), dir.x());
    poses.emplace_back(body_rotation(yaw, t.pitch_deg) * mount, position, "trajectory");
  }
  return poses;
}

}  // namespace sarmap::sim
