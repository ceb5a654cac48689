// The occupied voxels of class wall or other as boxes for the wall scene:
// each column's vertical runs, then runs merged with their neighbours where
// they share extents. Merging keeps the same solid in far fewer boxes (a
// straight wall becomes one box instead of one per column), and the wall
// scene is rebuilt at every update, so its build time follows the box count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/flat_key_map.hpp"
#include "engine/geometry/oriented_box.hpp"
#include "engine/topo/voxel_columns.hpp"

namespace sarmap::topo {

// Voxels [x0, x1] x [y0, y1] x [z0, z1], inclusive, in voxel indices.
struct VoxelBox {
  std::int32_t x0 = 0, x1 = 0, y0 = 0, y1 = 0, z0 = 0, z1 = 0;
  bool operator==(const VoxelBox&) const = default;
  bool contains(std::int32_t x, std::int32_t y, std::int32_t z) const {
    return x >= x0 && x <= x1 && y >= y0 && y <= y1 && z >= z0 && z <= z1;
  }
};

// Every vertical run of wall or other voxels, one column wide, in column
// order (y, then x, then z).
std::vector<VoxelBox> obstacle_runs(const VoxelColumns& columns);
// The runs of the columns within `within` (voxel indices), in the same
// order, into `runs` (emptied first), on its storage while that holds them.
void obstacle_runs(const VoxelColumns& columns, const ColumnRect& within, std::vector<VoxelBox>& runs);

// What merge_runs needs between its two merges, kept by a caller that merges
// at every update so that its arrays are not made anew each time.
struct BoxMergeScratch {
  std::vector<VoxelBox> strips;
  FlatKeyMap<std::uint32_t> open;

  std::size_t memory_bytes() const { return capacity_bytes(strips) + open.memory_bytes(); }
};

// The same voxels in fewer boxes: runs merged along x where neighbouring
// columns of a row hold a run of the same heights, then those strips along y
// where neighbouring rows hold one of the same x extent and heights. `runs`
// in obstacle_runs' order; the result is deterministic.
std::vector<VoxelBox> merge_runs(std::span<const VoxelBox> runs);
// The same into `merged` (emptied first), on its and the scratch's storage.
void merge_runs(std::span<const VoxelBox> runs, BoxMergeScratch& scratch, std::vector<VoxelBox>& merged);

// The box's space in metres, grown by `grow` on every side.
geometry::OrientedBox grown_box(const VoxelBox& box, double resolution, double grow);

}  // namespace sarmap::topo
