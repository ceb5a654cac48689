// Exact (double precision, Embree-free) tests of a segment against an oriented
// box: the reference TriangleScene's float answers are tested and benchmarked
// against, and the distances that tell where float may legitimately differ.
#pragma once

#include <Eigen/Core>

#include "engine/geometry/float_limits.hpp"
#include "engine/geometry/oriented_box.hpp"
#include "engine/geometry/segment.hpp"

namespace sarmap::geometry {

// Whether the segment and the solid box share a point: crossing it, touching
// a face, edge or corner (touching counts), or lying inside it. A zero-length
// segment asks whether its point is in the box (boundary included). A slab
// test in the box's frame. Throws sarmap::Error (InvalidArgument) for a
// non-finite endpoint.
bool segment_intersects_box(const Segment& segment, const OrientedBox& box);

// Whether the segment meets the box's surface: what a TriangleScene holding
// the box's closed mesh answers. The same as segment_intersects_box except for
// a segment lying wholly inside the box (a surface-only scene cannot see it).
bool segment_meets_box_surface(const Segment& segment, const OrientedBox& box);

// Signed distance from a point to the box's surface: the Euclidean distance
// to the box outside, minus the distance to the nearest face inside, 0 on it.
double signed_distance(const Eigen::Vector3d& point, const OrientedBox& box);

// The least signed distance to the box's surface over the segment's points:
// > 0 is the gap by which a segment misses the box, <= 0 is minus how deep it
// reaches in. Exact up to double rounding (the minimum of a convex piecewise
// function, taken over its pieces).
double segment_box_signed_distance(const Segment& segment, const OrientedBox& box);

// Whether moving the segment or the box's faces by `tolerance` could change
// either answer above: the segment passes within it of the box, reaches into
// the box by less than it, or its outer endpoint lies within it of the
// surface. Only for such segments may a float scene differ from the reference.
bool segment_near_box_surface(const Segment& segment, const OrientedBox& box,
                              double tolerance = kSurfaceTolerance);

}  // namespace sarmap::geometry
