// The distinct voxels a scan's points end in, in order of each voxel's first
// point, with what those points say about its class: the end-voxel dedupe of
// ray integration (each voxel is cast once and updated once per scan).
//
// Grouping runs in point order on one thread, so the float sums of class
// scores do not depend on the thread count. A voxel is found through a dense
// table over the box of the scan's end voxels when the box is small enough —
// one load per point, and neighbouring points of a depth image share cache
// lines — or else through a hash table; both give the same groups.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "engine/core/point_buffer.hpp"
#include "engine/metric/flat_key_index.hpp"
#include "engine/metric/label_fusion.hpp"
#include "engine/metric/voxel_key.hpp"

namespace sarmap::metric {

// Inclusive box of voxel keys.
struct VoxelBox {
  VoxelKey lo{std::numeric_limits<std::int32_t>::max(), std::numeric_limits<std::int32_t>::max(),
              std::numeric_limits<std::int32_t>::max()};
  VoxelKey hi{std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::min(),
              std::numeric_limits<std::int32_t>::min()};

  bool empty() const { return lo.x > hi.x; }
  // Inline: called once per point.
  void add(const VoxelKey& k) {
    lo = {k.x < lo.x ? k.x : lo.x, k.y < lo.y ? k.y : lo.y, k.z < lo.z ? k.z : lo.z};
    hi = {k.x > hi.x ? k.x : hi.x, k.y > hi.y ? k.y : hi.y, k.z > hi.z ? k.z : hi.z};
  }
  void add(const VoxelBox& b) {
    if (b.empty()) return;
    add(b.lo);
    add(b.hi);
  }
  // Cells in the box (0 when empty); saturates instead of overflowing.
  std::size_t cells() const;
};

class EndVoxelGroups {
 public:
  // Groups the points i with ends[i] != 0 by their voxel at inv_resolution
  // (every such point is within the map limits and its voxel inside box).
  // Observations take per-class scores when use_scores and points has a
  // score channel named after every class, else the labels (class 0 without
  // labels). The dense table is used when box has at most max_dense_cells
  // cells. (Keys are recomputed here rather than passed in: writing and
  // reading 12 bytes per point cost more than the arithmetic.)
  void group(const PointBuffer& points, double inv_resolution, std::span<const std::uint8_t> ends,
             const VoxelBox& box, bool use_scores, std::size_t max_dense_cells);

  std::size_t size() const { return keys_.size(); }
  const std::vector<VoxelKey>& keys() const { return keys_; }
  const std::vector<ClassObservation>& observations() const { return observations_; }
  // Whether the last group() used the dense table (for tests).
  bool used_dense_table() const { return used_dense_; }

 private:
  std::vector<VoxelKey> keys_;
  std::vector<ClassObservation> observations_;
  FlatKeyIndex hashed_{65536};
  // Dense table: group index + 1 per cell of the box, 0 for none; all zero
  // between calls (group() resets the cells it used).
  std::vector<std::uint32_t> dense_;
  bool used_dense_ = false;
};

}  // namespace sarmap::metric
