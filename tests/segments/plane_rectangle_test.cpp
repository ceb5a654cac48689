#include "engine/segments/plane_rectangle.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace sarmap::segments {
namespace {

TEST(ConvexHull, KeepsCornersDropsInteriorAndCollinearPoints) {
  std::vector<Eigen::Vector2d> p = {{0, 0}, {2, 0}, {2, 1}, {0, 1}, {1, 0}, {1, 0.5}, {0.3, 0.7}, {2, 0.5}};
  const auto hull = convex_hull(p);
  ASSERT_EQ(hull.size(), 4u);
  std::vector<Eigen::Vector2d> corners;
  for (auto i : hull) corners.push_back(p[i]);
  EXPECT_DOUBLE_EQ(polygon_area(corners), 2.0);
}

TEST(ConvexHull, DegenerateInputs) {
  EXPECT_TRUE(convex_hull(std::vector<Eigen::Vector2d>{}).empty());
  EXPECT_EQ(convex_hull(std::vector<Eigen::Vector2d>{{1, 1}}).size(), 1u);
  EXPECT_EQ(convex_hull(std::vector<Eigen::Vector2d>{{1, 1}, {1, 1}, {1, 1}}).size(), 1u);
  EXPECT_EQ(convex_hull(std::vector<Eigen::Vector2d>{{0, 0}, {1, 1}, {2, 2}, {3, 3}}).size(), 2u);
}

TEST(MinAreaRectangle, RecoversARotatedRectangleExactly) {
  const double angle = 0.4;
  const Eigen::Vector2d a(std::cos(angle), std::sin(angle)), b(-std::sin(angle), std::cos(angle));
  const Eigen::Vector2d center(3, -1);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ua(-1.5, 1.5), ub(-0.4, 0.4);
  std::vector<Eigen::Vector2d> p;
  for (double sa : {-1.5, 1.5}) {
    for (double sb : {-0.4, 0.4}) p.push_back(center + sa * a + sb * b);
  }
  for (int i = 0; i < 300; ++i) p.push_back(center + ua(rng) * a + ub(rng) * b);
  const Rectangle2d r = min_area_rectangle(p);
  EXPECT_NEAR(r.half_extents[0], 1.5, 1e-9);
  EXPECT_NEAR(r.half_extents[1], 0.4, 1e-9);
  EXPECT_NEAR(std::abs(r.axes[0].dot(a)), 1.0, 1e-9);
  EXPECT_TRUE(r.center.isApprox(center, 1e-9));
  // Right-handed frame.
  EXPECT_NEAR(r.axes[0].x() * r.axes[1].y() - r.axes[0].y() * r.axes[1].x(), 1.0, 1e-12);
}

TEST(MinAreaRectangle, SmallerThanTheAxisAlignedBoxForADiamond) {
  std::vector<Eigen::Vector2d> p = {{0, 1}, {1, 0}, {0, -1}, {-1, 0}};
  const Rectangle2d r = min_area_rectangle(p);
  EXPECT_NEAR(4 * r.half_extents[0] * r.half_extents[1], 2.0, 1e-12);  // the diamond itself, not 4
}

TEST(MinAreaRectangle, OnePointAndASegment) {
  const Rectangle2d one = min_area_rectangle(std::vector<Eigen::Vector2d>{{2, 3}});
  EXPECT_EQ(one.center, Eigen::Vector2d(2, 3));
  EXPECT_EQ(one.half_extents[0], 0);
  const Rectangle2d line = min_area_rectangle(std::vector<Eigen::Vector2d>{{0, 0}, {2, 0}, {1, 0}});
  EXPECT_NEAR(line.half_extents[0], 1.0, 1e-12);
  EXPECT_NEAR(line.half_extents[1], 0.0, 1e-12);
}

}  // namespace
}  // namespace sarmap::segments
