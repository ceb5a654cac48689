// The outline of a segment in its plane: the convex hull of its points and
// the minimum-area rectangle around it (an edge of the smallest enclosing
// rectangle lies on a hull edge, so trying each hull edge finds it).
#pragma once

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace sarmap::segments {

// Convex hull, counter-clockwise, without collinear points; one point for a
// single point, two for collinear points. Indices into `points`.
std::vector<std::size_t> convex_hull(std::span<const Eigen::Vector2d> points);

// Area of a simple polygon (shoelace), m^2; 0 below three points.
double polygon_area(std::span<const Eigen::Vector2d> polygon);

struct Rectangle2d {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  std::array<Eigen::Vector2d, 2> axes{Eigen::Vector2d::UnitX(), Eigen::Vector2d::UnitY()};
  std::array<double, 2> half_extents{0, 0};  // the first is the larger
};

// Smallest-area rectangle holding every point (zero extents for one point).
Rectangle2d min_area_rectangle(std::span<const Eigen::Vector2d> points);

}  // namespace sarmap::segments
