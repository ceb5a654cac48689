// The voxels a segment passes through: kernels/dda_walk.hpp's exact DDA
// (Amanatides & Woo, with its tie rule and exact termination) over the voxel
// grid, handing out VoxelKeys.
#pragma once

#include <cstddef>

#include "engine/metric/voxel_key.hpp"
#include "kernels/dda_walk.hpp"

namespace sarmap::metric {

inline constexpr float kRayTieParameter = kernels::kDdaTieParameter;

// start and end are in voxel units (coordinate / resolution, so voxel faces
// are at integers). visit(const VoxelKey&) returns false to stop early.
// Visits from the start's voxel up to, not including, the end's. Returns the
// number of voxels visited.
template <class Visit>
inline std::size_t walk_ray(const double start[3], const double end[3], Visit&& visit) {
  return kernels::dda_walk(start, end, [&](std::int32_t x, std::int32_t y, std::int32_t z) {
    return visit(VoxelKey{x, y, z});
  });
}

}  // namespace sarmap::metric
