#include "engine/segments/walkable.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace sarmap::segments {

bool is_walkable(const Segment& s) {
  return (s.label == ClassId::Terrain || s.label == ClassId::FlatRamp || s.label == ClassId::InclinedRamp) &&
         s.plane.normal.z() >= std::cos(std::numbers::pi / 4);
}

double height_at(const Segment& s, double x, double y) {
  const Plane& p = s.plane;
  return -(p.normal.x() * x + p.normal.y() * y + p.offset) / p.normal.z();
}

const Segment* segment_under(const std::vector<const Segment*>& segments, const Eigen::Vector3d& p, double max_drop,
                             double tolerance) {
  const Segment* best = nullptr;
  double best_z = -std::numeric_limits<double>::infinity();
  for (const Segment* s : segments) {
    if (!is_walkable(*s)) continue;
    const double z = height_at(*s, p.x(), p.y());
    if (z > p.z() + tolerance || p.z() - z > max_drop) continue;
    if (!s->covers({p.x(), p.y(), z}, 0)) continue;
    if (z > best_z) {
      best_z = z;
      best = s;
    }
  }
  return best;
}

}  // namespace sarmap::segments
