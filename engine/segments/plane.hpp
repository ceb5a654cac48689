// A plane n . x + offset = 0 with a unit normal, and the in-plane frame that
// projects points onto it (u, v, n right-handed; for a wall u runs along it
// horizontally), so every segment step agrees on 2-D coordinates.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace sarmap::segments {

struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit length
  double offset = 0;

  // Signed distance: positive on the side the normal points to.
  double distance(const Eigen::Vector3d& p) const { return normal.dot(p) + offset; }
  // Angle from horizontal, degrees (0 for a floor, 90 for a wall).
  double slope_deg() const;
};

// Orthonormal in-plane axes for a unit normal: u level when the plane slopes
// 10 degrees or more (along a wall, across a ramp), else u follows +x.
struct PlaneFrame {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();
  Eigen::Vector3d v = Eigen::Vector3d::UnitY();

  PlaneFrame() = default;
  PlaneFrame(const Eigen::Vector3d& origin, const Eigen::Vector3d& normal);

  Eigen::Vector2d project(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = p - origin;
    return {d.dot(u), d.dot(v)};
  }
  Eigen::Vector3d lift(const Eigen::Vector2d& q) const { return origin + q.x() * u + q.y() * v; }
};

}  // namespace sarmap::segments
