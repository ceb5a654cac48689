#include "engine/metric/grid_hit_list.hpp"

#include "engine/core/capacity_bytes.hpp"

namespace sarmap::metric {

void sort_hits_by_block(std::span<const std::uint8_t> is_hit, std::span<const std::uint32_t> block_of_hit,
                        std::size_t blocks, std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& hits) {
  // Each block's count, summed into the end of its place; the hits then
  // placed from the last one back, which leaves start[b] at block b's first.
  start.assign(blocks + 1, 0);
  for (const std::uint32_t b : block_of_hit) ++start[b];
  for (std::size_t b = 1; b < blocks; ++b) start[b] += start[b - 1];
  start[blocks] = static_cast<std::uint32_t>(block_of_hit.size());
  hits.resize(block_of_hit.size());
  std::size_t k = block_of_hit.size();
  for (std::size_t u = is_hit.size(); u-- > 0;) {
    if (is_hit[u]) hits[--start[block_of_hit[--k]]] = static_cast<std::uint32_t>(u);
  }
}

bool GridHitList::build(const kernels::DenseMaskGrid& grid, std::span<const VoxelKey> ends,
                        std::span<const std::uint8_t> is_hit) {
  listed_ = false;
  const auto extent = [&](int axis) { return static_cast<std::uint32_t>(grid.blocks[axis]); };
  block_of_hit_.clear();
  for (std::size_t u = 0; u < ends.size(); ++u) {
    if (!is_hit[u]) continue;
    const BlockKey b = block_of(ends[u]);
    // Unsigned, so that a block before the grid's first wraps to a large offset.
    const std::uint32_t i = static_cast<std::uint32_t>(b.x - grid.first_block[0]);
    const std::uint32_t j = static_cast<std::uint32_t>(b.y - grid.first_block[1]);
    const std::uint32_t k = static_cast<std::uint32_t>(b.z - grid.first_block[2]);
    if (i >= extent(0) || j >= extent(1) || k >= extent(2)) return false;
    block_of_hit_.push_back(i + extent(0) * (j + extent(1) * k));
  }
  sort_hits_by_block(is_hit, block_of_hit_, kernels::dense_grid_blocks(grid), start_, hits_);
  listed_ = true;
  return true;
}

std::size_t GridHitList::memory_bytes() const {
  return capacity_bytes(start_) + capacity_bytes(hits_) + capacity_bytes(block_of_hit_);
}

}  // namespace sarmap::metric
