#include "engine/segments/plane.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sarmap::segments {

double Plane::slope_deg() const {
  return std::acos(std::clamp(std::abs(normal.z()), 0.0, 1.0)) * 180.0 / std::numbers::pi;
}

PlaneFrame::PlaneFrame(const Eigen::Vector3d& o, const Eigen::Vector3d& n) : origin(o) {
  // |z x n| is the sine of the slope: from 10 degrees on (every ramp and
  // wall) it is long enough to be a stable axis, and u then runs level across
  // the slope; a floor's tiny, noisy z x n would turn u at random.
  const Eigen::Vector3d zn = Eigen::Vector3d::UnitZ().cross(n);
  if (zn.norm() > 0.17) {
    u = zn.normalized();
  } else {
    u = (Eigen::Vector3d::UnitX() - n.x() * n).normalized();
  }
  v = n.cross(u);
}

}  // namespace sarmap::segments
