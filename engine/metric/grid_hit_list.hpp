// A scan's hits (the end voxels within range) listed by block of the scan's
// dense mask grid: a counting sort, so that the update finds each block's
// hits without a look-up per hit or a sort of its own. ScanRays lists them
// while the rays are walked; the update's serial part then has nothing to
// list (ScanUpdate::apply).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/metric/voxel_key.hpp"
#include "kernels/ray_marking.hpp"

namespace sarmap::metric {

// The counting sort both listings of a scan's hits use (GridHitList by
// grid block, ScanUpdate by merged block when there is no such list): the
// ends u with is_hit[u], the k-th of them in block block_of_hit[k] (below
// blocks), listed by block and in end order within one. Block b's hits are
// hits[start[b] .. start[b + 1]) (start gets blocks + 1 entries).
void sort_hits_by_block(std::span<const std::uint8_t> is_hit, std::span<const std::uint32_t> block_of_hit,
                        std::size_t blocks, std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& hits);

class GridHitList {
 public:
  // Lists every end u with is_hit[u] by its block of grid, in end order
  // within a block. Returns false and lists nothing when a hit lies outside
  // the grid (the caller then lists the hits some other way).
  bool build(const kernels::DenseMaskGrid& grid, std::span<const VoxelKey> ends,
             std::span<const std::uint8_t> is_hit);
  // Forgets the list (listed() is false until the next build()).
  void clear() { listed_ = false; }

  bool listed() const { return listed_; }
  // Grid block g's hits are hits()[begin(g) .. begin(g + 1)): end indices.
  std::uint32_t begin(std::size_t g) const { return start_[g]; }
  std::span<const std::uint32_t> hits() const { return hits_; }
  // Bytes held (by capacity).
  std::size_t memory_bytes() const;

 private:
  bool listed_ = false;
  std::vector<std::uint32_t> start_;  // per grid block, and one past the last
  std::vector<std::uint32_t> hits_;
  std::vector<std::uint32_t> block_of_hit_;  // scratch: each hit's grid block, in end order
};

}  // namespace sarmap::metric
