// Which segments a robot can stand on, and the one under a point: the
// queries node placement and path planning ask of the segments.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "engine/segments/segment.hpp"

namespace sarmap::segments {

// Terrain, flat ramp or inclined ramp less than 45 degrees steep.
bool is_walkable(const Segment& segment);

// The highest walkable segment whose rectangle holds p's vertical projection
// and whose surface there lies at most `max_drop` below p and at most
// `tolerance` above it; nullptr if none. Ties go to the first in the list.
const Segment* segment_under(const std::vector<const Segment*>& segments, const Eigen::Vector3d& p, double max_drop,
                             double tolerance);

// Height of the segment's plane at (x, y); the plane must not be vertical.
double height_at(const Segment& segment, double x, double y);

}  // namespace sarmap::segments
