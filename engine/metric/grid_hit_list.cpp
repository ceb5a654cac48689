#include "engine/metric/grid_hit_list.hpp"

#include "engine/core/capacity_bytes.hpp"

namespace sarmap::metric {

bool GridHitList::build(const kernels::DenseMaskGrid& grid, std::span<const VoxelKey> ends,
                        std::span<const std::uint8_t> is_hit) {
  listed_ = false;
  const auto extent = [&](int axis) { return static_cast<std::uint32_t>(grid.blocks[axis]); };
  // Each hit's block, counted per block (shifted by one) as it is found.
  start_.assign(kernels::dense_grid_blocks(grid) + 1, 0);
  block_of_hit_.resize(ends.size());
  std::size_t hits = 0;
  for (std::size_t u = 0; u < ends.size(); ++u) {
    if (!is_hit[u]) continue;
    const BlockKey b = block_of(ends[u]);
    // Unsigned, so that a block before the grid's first wraps to a large offset.
    const std::uint32_t i = static_cast<std::uint32_t>(b.x - grid.first_block[0]);
    const std::uint32_t j = static_cast<std::uint32_t>(b.y - grid.first_block[1]);
    const std::uint32_t k = static_cast<std::uint32_t>(b.z - grid.first_block[2]);
    if (i >= extent(0) || j >= extent(1) || k >= extent(2)) return false;
    const std::uint32_t g = i + extent(0) * (j + extent(1) * k);
    block_of_hit_[hits++] = g;
    ++start_[g + 1];
  }
  // Summed into each block's first place, then the hits placed in end order.
  for (std::size_t g = 1; g < start_.size(); ++g) start_[g] += start_[g - 1];
  hits_.resize(hits);
  std::size_t h = 0;
  for (std::uint32_t u = 0; u < ends.size(); ++u) {
    if (!is_hit[u]) continue;
    hits_[start_[block_of_hit_[h++]]++] = u;
  }
  // Each block's place has moved to the next block's first: shift back.
  for (std::size_t g = start_.size() - 1; g > 0; --g) start_[g] = start_[g - 1];
  start_[0] = 0;
  listed_ = true;
  return true;
}

std::size_t GridHitList::memory_bytes() const {
  return capacity_bytes(start_) + capacity_bytes(hits_) + capacity_bytes(block_of_hit_);
}

}  // namespace sarmap::metric
