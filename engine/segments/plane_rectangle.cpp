#include "engine/segments/plane_rectangle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace sarmap::segments {
namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

}  // namespace

std::vector<std::size_t> convex_hull(std::span<const Eigen::Vector2d> p) {
  if (p.empty()) return {};
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&p](std::size_t a, std::size_t b) {
    return p[a].x() != p[b].x() ? p[a].x() < p[b].x() : (p[a].y() != p[b].y() ? p[a].y() < p[b].y() : a < b);
  });
  // Andrew's monotone chain: lower hull left to right, upper hull back.
  std::vector<std::size_t> hull(2 * order.size() + 1);
  std::size_t k = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    while (k >= 2 && cross(p[hull[k - 2]], p[hull[k - 1]], p[order[i]]) <= 0) --k;
    hull[k++] = order[i];
  }
  for (std::size_t i = order.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(p[hull[k - 2]], p[hull[k - 1]], p[order[i]]) <= 0) --k;
    hull[k++] = order[i];
  }
  if (k > 1) --k;  // the last point repeats the first
  hull.resize(k);
  // Repeated points: a hull of two equal points is one point.
  if (hull.size() == 2 && p[hull[0]] == p[hull[1]]) hull.resize(1);
  return hull;
}

double polygon_area(std::span<const Eigen::Vector2d> q) {
  if (q.size() < 3) return 0;
  double twice = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const Eigen::Vector2d& a = q[i];
    const Eigen::Vector2d& b = q[(i + 1) % q.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return std::abs(twice) / 2;
}

Rectangle2d min_area_rectangle(std::span<const Eigen::Vector2d> points) {
  Rectangle2d best;
  if (points.empty()) return best;
  const std::vector<std::size_t> hull = convex_hull(points);
  if (hull.size() == 1) {
    best.center = points[hull[0]];
    return best;
  }
  double best_area = std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < hull.size(); ++e) {
    const Eigen::Vector2d edge = points[hull[(e + 1) % hull.size()]] - points[hull[e]];
    const double length = edge.norm();
    if (!(length > 0)) continue;
    const Eigen::Vector2d a = edge / length;
    const Eigen::Vector2d b(-a.y(), a.x());
    double lo_a = std::numeric_limits<double>::infinity(), hi_a = -lo_a, lo_b = lo_a, hi_b = -lo_a;
    for (std::size_t h : hull) {
      const double pa = points[h].dot(a), pb = points[h].dot(b);
      lo_a = std::min(lo_a, pa);
      hi_a = std::max(hi_a, pa);
      lo_b = std::min(lo_b, pb);
      hi_b = std::max(hi_b, pb);
    }
    const double area = (hi_a - lo_a) * (hi_b - lo_b);
    // Strictly smaller only, so the first edge wins ties and the result is stable.
    if (area < best_area - 1e-12) {
      best_area = area;
      best.center = a * (lo_a + hi_a) / 2 + b * (lo_b + hi_b) / 2;
      best.axes = {a, b};
      best.half_extents = {(hi_a - lo_a) / 2, (hi_b - lo_b) / 2};
    }
  }
  if (best.half_extents[1] > best.half_extents[0]) {
    std::swap(best.half_extents[0], best.half_extents[1]);
    // Keep the frame right-handed: (a, b) -> (b, -a).
    best.axes = {best.axes[1], Eigen::Vector2d(-best.axes[0])};
  }
  return best;
}

}  // namespace sarmap::segments
