#include "engine/segments/segment_merge.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace sarmap::segments {
namespace {

using Quad = std::array<Eigen::Vector2d, 4>;

double point_segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Separating-axis test of two convex quads (either winding); touching counts as overlapping.
bool quads_overlap(const Quad& a, const Quad& b) {
  for (const Quad* q : {&a, &b}) {
    for (std::size_t i = 0; i < 4; ++i) {
      const Eigen::Vector2d edge = (*q)[(i + 1) % 4] - (*q)[i];
      const Eigen::Vector2d axis(-edge.y(), edge.x());
      if (!(axis.squaredNorm() > 0)) continue;
      double lo_a = std::numeric_limits<double>::infinity(), hi_a = -lo_a, lo_b = lo_a, hi_b = -lo_a;
      for (const Eigen::Vector2d& p : a) {
        lo_a = std::min(lo_a, p.dot(axis));
        hi_a = std::max(hi_a, p.dot(axis));
      }
      for (const Eigen::Vector2d& p : b) {
        lo_b = std::min(lo_b, p.dot(axis));
        hi_b = std::max(hi_b, p.dot(axis));
      }
      if (hi_a < lo_b || hi_b < lo_a) return false;
    }
  }
  return true;
}

}  // namespace

double rectangle_gap(const Segment& a, const Segment& b) {
  const PlaneFrame frame(a.rectangle.center, a.plane.normal);
  Quad qa, qb;
  const auto ca = a.rectangle.corners();
  const auto cb = b.rectangle.corners();
  for (std::size_t i = 0; i < 4; ++i) {
    qa[i] = frame.project(ca[i]);
    qb[i] = frame.project(cb[i]);
  }
  if (quads_overlap(qa, qb)) return 0;
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < 4; ++i) {
    for (std::size_t k = 0; k < 4; ++k) {
      gap = std::min(gap, point_segment_distance(qa[i], qb[k], qb[(k + 1) % 4]));
      gap = std::min(gap, point_segment_distance(qb[i], qa[k], qa[(k + 1) % 4]));
    }
  }
  return gap;
}

bool same_surface(const Segment& a, const Segment& b, const SegmentSettings& s) {
  if (a.label != b.label) return false;
  // The smaller segment's centroid against the larger one's plane: a small
  // segment's plane, tilted by a degree, would miss a far centroid.
  const Segment& large = a.inliers >= b.inliers ? a : b;
  const Segment& small = a.inliers >= b.inliers ? b : a;
  if (std::abs(large.plane.distance(small.centroid)) > s.merge_offset) return false;
  const bool on_it = large.covers(small.centroid, 0);
  const double angle = on_it ? s.merge_overlap_angle_deg : s.merge_angle_deg;
  if (a.plane.normal.dot(b.plane.normal) < std::cos(angle * std::numbers::pi / 180.0)) return false;
  return on_it || rectangle_gap(a, b) <= s.merge_gap;
}

}  // namespace sarmap::segments
