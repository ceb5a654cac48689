// Ground truth of an arena as voxels at a resolution, to score metric maps:
// occupied voxels (touched by a surface, with the class covering most of the
// voxel's surface area, found by clipping every triangle to the voxel grid)
// and free voxels (inside the bounds, crossed by a noise-free ray of the
// arena's own sensor and trajectory before it hits, and holding no surface).
//
// Keys are floor(coord / resolution) per axis, the convention the metric map
// uses. A flat surface lying exactly on a voxel face (the floor at z = 0, a
// wall face at a multiple of the resolution) touches the voxels on both sides
// and is occupied in both, half its area in each: sensor points on such a
// surface land on both sides of the face.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/arena_mesh.hpp"

namespace sarmap::sim {

class Simulator;

struct VoxelKey {
  std::int32_t x = 0, y = 0, z = 0;
  friend bool operator==(const VoxelKey&, const VoxelKey&) = default;
};

struct VoxelKeyHash {
  std::size_t operator()(const VoxelKey& k) const noexcept {
    // The usual large-prime spatial hash (Teschner et al.).
    return (static_cast<std::size_t>(static_cast<std::uint32_t>(k.x)) * 73856093u) ^
           (static_cast<std::size_t>(static_cast<std::uint32_t>(k.y)) * 19349663u) ^
           (static_cast<std::size_t>(static_cast<std::uint32_t>(k.z)) * 83492791u);
  }
};

inline VoxelKey voxel_key_of(const Eigen::Vector3d& p, double resolution) {
  return {static_cast<std::int32_t>(std::floor(p.x() / resolution)),
          static_cast<std::int32_t>(std::floor(p.y() / resolution)),
          static_cast<std::int32_t>(std::floor(p.z() / resolution))};
}
inline Eigen::Vector3d voxel_center(const VoxelKey& k, double resolution) {
  return {(k.x + 0.5) * resolution, (k.y + 0.5) * resolution, (k.z + 0.5) * resolution};
}

struct OccupiedVoxel {
  ClassId label = ClassId::Unknown;  // the class with the most area (ties: lower id)
  bool observed = false;             // a noise-free ray of the trajectory ends in it
  std::array<double, kClassCount> area{};  // surface area per class inside the voxel, m^2
};

using OccupiedVoxelMap = std::unordered_map<VoxelKey, OccupiedVoxel, VoxelKeyHash>;
using VoxelSet = std::unordered_set<VoxelKey, VoxelKeyHash>;

struct GroundTruthOptions {
  double resolution = 0.05;
  // False skips the ray casting: free is empty and no voxel is observed.
  bool compute_free = true;
  // Casts every n-th frame and every n-th row and column of the sensor; 1 is
  // exact, larger values trade completeness for speed.
  std::size_t frame_stride = 1;
  std::size_t ray_stride = 1;
};

struct GroundTruthGrid {
  enum class State : std::uint8_t { Unknown, Free, Occupied };

  double resolution = 0.05;
  OccupiedVoxelMap occupied;
  VoxelSet free;
  // Voxel key range of the arena bounds (inclusive): free voxels lie inside.
  VoxelKey bounds_min, bounds_max;

  State state(const VoxelKey& key) const {
    if (occupied.count(key)) return State::Occupied;
    return free.count(key) ? State::Free : State::Unknown;
  }
  // Class of an occupied voxel, Unknown for any other.
  ClassId label(const VoxelKey& key) const {
    const auto it = occupied.find(key);
    return it == occupied.end() ? ClassId::Unknown : it->second.label;
  }
  // Occupied voxels per dominant class (indexed by ClassId).
  std::array<std::size_t, kClassCount> occupied_per_class(bool observed_only = false) const;
};

// Adds the surface of one mesh to `out`: clips every triangle to the voxel
// grid and sums the area of each piece per class; recomputes labels.
void add_surface_voxels(const ClassedMesh& mesh, double resolution, OccupiedVoxelMap& out);

// Ground truth of an arena (builds its own simulator for the visibility rays).
GroundTruthGrid voxelize_arena(const Arena& arena, const GroundTruthOptions& options = {});
// The same from an existing simulator (its scene, rays and poses; noise is never applied).
GroundTruthGrid voxelize_arena(const Simulator& simulator, const GroundTruthOptions& options = {});

}  // namespace sarmap::sim
