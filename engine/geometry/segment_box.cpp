#include "engine/geometry/segment_box.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::geometry {
namespace {

void require_finite(const Segment& s, const char* where) {
  if (!s.p.allFinite() || !s.q.allFinite()) {
    throw Error(ErrorCode::InvalidArgument, std::string(where) + ": the segment has a non-finite endpoint");
  }
}

// The segment in the box's frame, where the box is [-h, h] on each axis:
// x(t) = a + t u for t in [0, 1].
struct LocalSegment {
  Eigen::Vector3d a, u;
};

LocalSegment to_box_frame(const Segment& s, const OrientedBox& box) {
  const Eigen::Vector3d a = box.axes.transpose() * (s.p - box.center);
  const Eigen::Vector3d b = box.axes.transpose() * (s.q - box.center);
  return {a, b - a};
}

// max_i |x_i| - h_i: the signed distance inside the box (where it is <= 0),
// and a convex piecewise-linear function of t along a segment.
double box_chebyshev(const Eigen::Vector3d& x, const Eigen::Vector3d& h) {
  return (x.cwiseAbs() - h).maxCoeff();
}

double outside_distance_squared(const Eigen::Vector3d& x, const Eigen::Vector3d& h) {
  return (x.cwiseAbs() - h).cwiseMax(0.0).squaredNorm();
}

// min over t in [0, 1] of box_chebyshev(a + t u): the maximum of the six lines
// +-(a_i + t u_i) - h_i is least at an end or where two of them cross.
double min_chebyshev(const LocalSegment& s, const Eigen::Vector3d& h) {
  std::array<double, 6> slope, offset;
  for (int i = 0; i < 3; ++i) {
    slope[2 * i] = s.u[i];
    offset[2 * i] = s.a[i] - h[i];
    slope[2 * i + 1] = -s.u[i];
    offset[2 * i + 1] = -s.a[i] - h[i];
  }
  double best = std::min(box_chebyshev(s.a, h), box_chebyshev(s.a + s.u, h));
  for (int j = 0; j < 6; ++j) {
    for (int k = j + 1; k < 6; ++k) {
      const double ds = slope[j] - slope[k];
      if (ds == 0) continue;
      const double t = (offset[k] - offset[j]) / ds;
      if (t > 0 && t < 1) best = std::min(best, box_chebyshev(s.a + t * s.u, h));
    }
  }
  return best;
}

// min over t in [0, 1] of the squared distance from a + t u to the box. Each
// coordinate's excess max(|x_i| - h_i, 0) is linear between the t where x_i
// crosses -h_i or h_i, so the squared distance is one quadratic per piece;
// the least value is at a piece's end or its quadratic's vertex.
double min_outside_distance_squared(const LocalSegment& s, const Eigen::Vector3d& h) {
  std::array<double, 8> cuts{};
  std::size_t n = 0;
  cuts[n++] = 0;
  cuts[n++] = 1;
  for (int i = 0; i < 3; ++i) {
    if (s.u[i] == 0) continue;
    for (double side : {-h[i], h[i]}) {
      const double t = (side - s.a[i]) / s.u[i];
      if (t > 0 && t < 1) cuts[n++] = t;
    }
  }
  // Insertion sort: at most 8 values (std::sort here trips GCC 12's -Warray-bounds).
  for (std::size_t i = 1; i < n; ++i) {
    for (std::size_t j = i; j > 0 && cuts[j] < cuts[j - 1]; --j) std::swap(cuts[j], cuts[j - 1]);
  }
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < n; ++c) best = std::min(best, outside_distance_squared(s.a + cuts[c] * s.u, h));
  for (std::size_t c = 0; c + 1 < n; ++c) {
    const double t0 = cuts[c], t1 = cuts[c + 1];
    if (!(t1 > t0)) continue;
    const Eigen::Vector3d mid = s.a + (0.5 * (t0 + t1)) * s.u;
    // On this piece the excess along axis i is sign * (a_i + t u_i) - h_i or 0.
    double qa = 0, qb = 0;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(mid[i]) <= h[i]) continue;
      const double sign = mid[i] > 0 ? 1.0 : -1.0;
      const double slope = sign * s.u[i];
      const double offset = sign * s.a[i] - h[i];
      qa += slope * slope;
      qb += 2 * slope * offset;
    }
    if (qa <= 0) continue;
    const double t = -qb / (2 * qa);
    if (t > t0 && t < t1) best = std::min(best, outside_distance_squared(s.a + t * s.u, h));
  }
  return best;
}

}  // namespace

bool segment_intersects_box(const Segment& segment, const OrientedBox& box) {
  require_finite(segment, "segment_intersects_box");
  const LocalSegment s = to_box_frame(segment, box);
  const Eigen::Vector3d& h = box.half_extents;
  double t0 = 0, t1 = 1;
  for (int i = 0; i < 3; ++i) {
    if (s.u[i] == 0) {
      // Parallel to this slab: inside it everywhere or nowhere.
      if (std::abs(s.a[i]) > h[i]) return false;
      continue;
    }
    // Division, not a reciprocal: a tiny u_i then gives +-infinity, never
    // the NaN of 0 * infinity.
    double lo = (-h[i] - s.a[i]) / s.u[i];
    double hi = (h[i] - s.a[i]) / s.u[i];
    if (lo > hi) std::swap(lo, hi);
    t0 = std::max(t0, lo);
    t1 = std::min(t1, hi);
    if (t0 > t1) return false;
  }
  return true;
}

bool segment_meets_box_surface(const Segment& segment, const OrientedBox& box) {
  if (!segment_intersects_box(segment, box)) return false;
  return !(signed_distance(segment.p, box) < 0 && signed_distance(segment.q, box) < 0);
}

double signed_distance(const Eigen::Vector3d& point, const OrientedBox& box) {
  if (!point.allFinite()) throw Error(ErrorCode::InvalidArgument, "signed_distance: the point is not finite");
  const Eigen::Vector3d x = box.axes.transpose() * (point - box.center);
  const double inside = box_chebyshev(x, box.half_extents);
  return inside <= 0 ? inside : std::sqrt(outside_distance_squared(x, box.half_extents));
}

double segment_box_signed_distance(const Segment& segment, const OrientedBox& box) {
  require_finite(segment, "segment_box_signed_distance");
  const LocalSegment s = to_box_frame(segment, box);
  // The signed distance equals the Chebyshev form wherever that is <= 0, and
  // is positive wherever it is positive, so a segment that enters the box has
  // the Chebyshev minimum as its least signed distance.
  const double inside = min_chebyshev(s, box.half_extents);
  if (inside <= 0) return inside;
  return std::sqrt(min_outside_distance_squared(s, box.half_extents));
}

bool segment_near_box_surface(const Segment& segment, const OrientedBox& box, double tolerance) {
  if (std::abs(segment_box_signed_distance(segment, box)) <= tolerance) return true;
  const double outer = std::max(signed_distance(segment.p, box), signed_distance(segment.q, box));
  return std::abs(outer) <= tolerance;
}

}  // namespace sarmap::geometry
