// When two segments are one surface: same class, normals within an angle,
// the smaller one's centroid near the larger one's plane, and rectangles that
// overlap or lie within a gap of each other (a doorway keeps two walls apart).
#pragma once

#include "engine/segments/segment.hpp"
#include "engine/segments/segment_settings.hpp"

namespace sarmap::segments {

// Distance between the two rectangles, both projected into a's plane
// (0 when they overlap), metres.
double rectangle_gap(const Segment& a, const Segment& b);

bool same_surface(const Segment& a, const Segment& b, const SegmentSettings& settings);

}  // namespace sarmap::segments
