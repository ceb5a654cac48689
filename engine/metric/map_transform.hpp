// A metric map moved into another frame by a rigid transform: a robot's map
// brought into the frame of the map it merges into (`sarmap merge
// --transform`).
//
// Each voxel of the moved map takes the value of the most occupied known
// source voxel it overlaps (sampled at its centre and at eight points a
// quarter voxel towards its corners, carried back by the inverse
// transform): no blending, so occupancy log-odds and class evidence stay
// values some observation made, and occupied wins, so resampling never
// opens a gap in a wall one voxel thick; it thickens it instead (1.5 to
// 2.15 times the volume at angles off the grid: the conservative side for
// a robot planning on the map). Exact, voxel for
// voxel, when the transform maps the voxel grid onto itself: a translation
// by whole voxels and a yaw by a multiple of 90 degrees
// (tests/metric/map_transform_test.cpp).
#pragma once

#include "engine/core/pose.hpp"
#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

// The map's voxels in the frame `transform` maps the map's frame into; the
// same settings. Voxels whose centre lands beyond the map's limits
// (kMaxCoordinate) are dropped.
MetricMap transformed_map(const MetricMap& map, const Pose& transform);

}  // namespace sarmap::metric
