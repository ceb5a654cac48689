// Occupied voxels as points: the centre of each occupied voxel with its class
// (label) and the class colour, for voxels.ply and the viewer.
#pragma once

#include "engine/core/point_buffer.hpp"
#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

// One point per occupied voxel, in (z, y, x) block order: x y z at the voxel
// centre, labels = dominant class, colours from the class table.
PointBuffer occupied_voxel_cloud(const MetricMap& map);

}  // namespace sarmap::metric
