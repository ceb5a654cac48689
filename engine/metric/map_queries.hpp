// Queries over a metric map that walk more than one voxel: the first occupied
// voxel along a ray, the voxels of a box by state, and frontier voxels (free
// voxels next to unknown space, where exploration continues).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "engine/core/bounds.hpp"
#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

struct RayHit {
  VoxelKey voxel;
  Eigen::Vector3d center;
  double distance = 0;  // from the ray origin to the voxel centre, metres
};

// First occupied voxel along origin + t * direction, t in [0, max_distance]
// metres, walked with the same exact DDA as integration (the origin's voxel
// included). nullopt if none, or if the origin is beyond the map limits.
// Throws sarmap::Error (InvalidArgument) for a zero or non-finite direction.
std::optional<RayHit> cast_ray(const MetricMap& map, const Eigen::Vector3d& origin,
                               const Eigen::Vector3d& direction, double max_distance);

// Calls fn(key) for every voxel in the given state whose centre lies in box
// (closed), in block order. VoxelState::Unknown visits nothing (unknown space
// is not stored); use frontier_voxels for the boundary of what is known.
void for_each_voxel_in_box(const MetricMap& map, const Bounds& box, VoxelState state,
                           const std::function<void(const VoxelKey&)>& fn);

// Free voxels with centre in box that have at least one unknown 6-neighbour.
std::vector<VoxelKey> frontier_voxels(const MetricMap& map, const Bounds& box);

}  // namespace sarmap::metric
