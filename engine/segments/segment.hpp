// One planar segment of the arena: a wall face, a ramp deck, a platform top,
// a stretch of floor, with its plane, outline and extent, as segments.json
// writes it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/segments/plane.hpp"

namespace sarmap::segments {

// A rectangle lying in a segment's plane.
struct SegmentRectangle {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  std::array<Eigen::Vector3d, 2> axes{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};  // unit, in the plane
  std::array<double, 2> half_extents{0, 0};  // along axes[0] (the longer) and axes[1], metres

  std::array<Eigen::Vector3d, 4> corners() const;
};

struct Segment {
  std::uint32_t id = 0;  // stable once given; a merge keeps the lower id
  ClassId label = ClassId::Unknown;
  // Unit normal up for floors, decks and platform tops (planes within 45
  // degrees of level); for steeper planes out of the solid, towards the side
  // the sensor saw it from.
  Plane plane;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::size_t inliers = 0;
  // Minimum-area rectangle of the points projected into the plane.
  SegmentRectangle rectangle;
  // Spread of the points across the plane: the thickness of a uniform slab
  // with the same variance (sqrt(12) standard deviations), metres.
  double thickness = 0;
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();  // axis-aligned extent
  double slope_deg = 0;  // from horizontal
  double area_m2 = 0;    // of the convex hull of the points in the plane

  // Whether p projected onto the plane lies in the rectangle grown by margin
  // (metres) on every side.
  bool covers(const Eigen::Vector3d& p, double margin) const;
};

}  // namespace sarmap::segments
