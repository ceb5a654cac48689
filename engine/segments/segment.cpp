#include "engine/segments/segment.hpp"

#include <cmath>

namespace sarmap::segments {

std::array<Eigen::Vector3d, 4> SegmentRectangle::corners() const {
  const Eigen::Vector3d a = axes[0] * half_extents[0];
  const Eigen::Vector3d b = axes[1] * half_extents[1];
  return {center - a - b, center + a - b, center + a + b, center - a + b};
}

bool Segment::covers(const Eigen::Vector3d& p, double margin) const {
  const Eigen::Vector3d d = p - rectangle.center;
  return std::abs(d.dot(rectangle.axes[0])) <= rectangle.half_extents[0] + margin &&
         std::abs(d.dot(rectangle.axes[1])) <= rectangle.half_extents[1] + margin;
}

}  // namespace sarmap::segments
