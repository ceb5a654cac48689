#include "engine/segments/segment_merge.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sarmap::segments {
namespace {

// A vertical wall face in the plane y = y0 facing -y, spanning x0..x1, z 0..1.
Segment wall(double x0, double x1, double y0 = 0) {
  Segment s;
  s.label = ClassId::Wall;
  s.plane = {-Eigen::Vector3d::UnitY(), y0};
  s.centroid = {(x0 + x1) / 2, y0, 0.5};
  s.rectangle.center = s.centroid;
  s.rectangle.axes = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ()};
  s.rectangle.half_extents = {(x1 - x0) / 2, 0.5};
  return s;
}

TEST(SegmentMerge, GapBetweenRectangles) {
  EXPECT_DOUBLE_EQ(rectangle_gap(wall(0, 1), wall(0.5, 2)), 0.0);
  EXPECT_NEAR(rectangle_gap(wall(0, 1), wall(1.8, 2)), 0.8, 1e-12);
  EXPECT_NEAR(rectangle_gap(wall(1.8, 2), wall(0, 1)), 0.8, 1e-12);
}

TEST(SegmentMerge, ADoorwayKeepsTwoWallsApartAndTouchingPartsMerge) {
  const SegmentSettings s;
  EXPECT_FALSE(same_surface(wall(0, 1.5), wall(2.3, 4), s));  // 0.8 m doorway
  EXPECT_TRUE(same_surface(wall(0, 1.5), wall(1.6, 4), s));   // 0.1 m: one wall seen in two parts
  EXPECT_FALSE(same_surface(wall(0, 1.5), wall(1.5, 4, -0.1), s));  // the parallel face 10 cm away
  Segment flipped = wall(1, 2);
  flipped.plane = {Eigen::Vector3d::UnitY(), 0};
  EXPECT_FALSE(same_surface(wall(0, 1.5), flipped, s));  // seen from the other side: the other face
  Segment other = wall(1, 2);
  other.label = ClassId::Other;
  EXPECT_FALSE(same_surface(wall(0, 1.5), other, s));
}

TEST(SegmentMerge, ATiltedSlabOnAKnownWallMergesAndBesideItDoesNot) {
  const SegmentSettings s;
  Segment big = wall(0, 4);
  big.inliers = 10000;
  Segment slab = wall(1, 2);
  slab.inliers = 500;
  const double tilt = 12 * std::numbers::pi / 180;  // past merge_angle_deg, within merge_overlap_angle_deg
  slab.plane.normal = Eigen::Vector3d(0, -std::cos(tilt), std::sin(tilt));
  slab.plane.offset = -slab.plane.normal.dot(slab.centroid);
  EXPECT_TRUE(same_surface(big, slab, s));
  Segment beside = slab;  // the same slab just past the wall's end: not on it
  beside.centroid.x() += 3.5;
  beside.rectangle.center.x() += 3.5;
  beside.plane.offset = -beside.plane.normal.dot(beside.centroid);
  EXPECT_FALSE(same_surface(big, beside, s));
  slab.plane.normal = Eigen::Vector3d(0, -std::cos(3 * tilt), std::sin(3 * tilt));
  slab.plane.offset = -slab.plane.normal.dot(slab.centroid);
  EXPECT_FALSE(same_surface(big, slab, s));  // 36 degrees: another surface
}

}  // namespace
}  // namespace sarmap::segments
