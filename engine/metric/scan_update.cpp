#include "engine/metric/scan_update.hpp"

#include <algorithm>
#include <bit>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/core/capacity_bytes.hpp"
#include "kernels/log_odds_misses.hpp"

namespace sarmap::metric {

static_assert(kernels::kUnknownLogOddsByte == kStoredUnknownLogOdds &&
                  kernels::kLogOddsBlockVoxels == kBlockVoxels &&
                  kernels::kLogOddsBlockWords == BlockMask{}.size(),
              "the miss kernel reads a block's slab as the map stores it");

std::uint32_t ScanUpdate::merged_index(std::uint64_t packed_block) {
  const std::uint32_t b = merged_.find_or_insert(packed_block);
  if (b == merged_miss_.size()) merged_miss_.emplace_back();
  return b;
}

std::size_t ScanUpdate::memory_bytes() const {
  return merged_.memory_bytes() + capacity_bytes(merged_miss_) + capacity_bytes(merged_hit_) +
         capacity_bytes(dense_grids_) + capacity_bytes(merged_of_grid_) + capacity_bytes(order_) +
         capacity_bytes(block_of_index_) + capacity_bytes(uniform_after_) + capacity_bytes(hit_list_) +
         capacity_bytes(hit_block_) + capacity_bytes(hit_cursor_) + capacity_bytes(hit_start_);
}

void ScanUpdate::apply(MetricMap& map, ScanRays& rays, IntegrationStats& stats) {
  // Pass 3: merge, add hits, create blocks in sorted order.
  merged_.clear();
  merged_miss_.clear();
  for (const ThreadMisses& t : rays.threads()) {
    const auto& keys = t.blocks.keys();
    for (std::size_t b = 0; b < keys.size(); ++b) {
      BlockMask& m = merged_miss_[merged_index(keys[b])];
      for (std::size_t w = 0; w < m.size(); ++w) m[w] |= t.miss[b][w];
    }
  }
  if (const auto& box = rays.dense_box()) {
    dense_grids_.clear();
    for (ThreadMisses& t : rays.threads()) {
      if (t.dense_in_use) dense_grids_.push_back(t.dense.data());
    }
    // The box's blocks in grid order; only those some ray crossed. Each
    // block's words are cleared once read, so the grids are all zero again.
    merged_of_grid_.resize(kernels::dense_grid_blocks(*box));
    std::size_t g = 0;
    for (std::int32_t k = 0; k < box->blocks[2]; ++k) {
      for (std::int32_t j = 0; j < box->blocks[1]; ++j) {
        for (std::int32_t i = 0; i < box->blocks[0]; ++i, ++g) {
          BlockMask m{};
          for (std::uint64_t* grid : dense_grids_) {
            std::uint64_t* words = grid + g * m.size();
            std::uint64_t any = 0;
            for (std::size_t w = 0; w < m.size(); ++w) any |= words[w];
            if (any == 0) continue;
            for (std::size_t w = 0; w < m.size(); ++w) m[w] |= words[w];
            std::fill(words, words + m.size(), 0);
          }
          std::uint64_t any = 0;
          for (std::uint64_t w : m) any |= w;
          merged_of_grid_[g] = FlatKeyIndex::kAbsent;
          if (any == 0) continue;
          const std::uint32_t b =
              merged_index(pack(box->first_block[0] + i, box->first_block[1] + j, box->first_block[2] + k));
          merged_miss_[b] = m;
          merged_of_grid_[g] = b;
        }
      }
    }
    rays.dense_grids_cleared();
  }
  // Hits: each in-range end voxel's block (created if no ray crossed it),
  // then the hits listed by block (a counting sort), so that pass 4 updates
  // a block's misses and hits in one task without looking blocks up again.
  const std::vector<VoxelKey>& end_keys = rays.ends().keys();
  const std::vector<std::uint8_t>& is_hit = rays.end_is_hit();
  hit_block_.clear();
  if (const auto& box = rays.dense_box()) {
    // Every hit is a ray's end, so its block is in the box: found by its
    // place in the grid rather than by hashing once per hit. The bounds are
    // checked all the same.
    const auto offset = [&](std::int32_t block, int axis) {
      return static_cast<std::uint32_t>(block - box->first_block[axis]);
    };
    for (std::uint32_t u = 0; u < end_keys.size(); ++u) {
      if (!is_hit[u]) continue;
      const BlockKey bk = block_of(end_keys[u]);
      const std::uint32_t i = offset(bk.x, 0), j = offset(bk.y, 1), k = offset(bk.z, 2);
      if (i >= static_cast<std::uint32_t>(box->blocks[0]) || j >= static_cast<std::uint32_t>(box->blocks[1]) ||
          k >= static_cast<std::uint32_t>(box->blocks[2])) {
        hit_block_.push_back(merged_index(pack(bk)));
        continue;
      }
      const std::size_t g = i + static_cast<std::size_t>(box->blocks[0]) *
                                    (j + static_cast<std::size_t>(box->blocks[1]) * k);
      std::uint32_t& b = merged_of_grid_[g];
      if (b == FlatKeyIndex::kAbsent) b = merged_index(pack(bk));  // a block no ray crossed
      hit_block_.push_back(b);
    }
  } else {
    for (std::uint32_t u = 0; u < end_keys.size(); ++u) {
      if (is_hit[u]) hit_block_.push_back(merged_index(pack(block_of(end_keys[u]))));
    }
  }
  merged_hit_.assign(merged_miss_.size(), BlockMask{});
  hit_start_.assign(merged_miss_.size() + 1, 0);
  for (std::uint32_t b : hit_block_) ++hit_start_[b + 1];
  for (std::size_t b = 1; b < hit_start_.size(); ++b) hit_start_[b] += hit_start_[b - 1];
  hit_list_.resize(hit_block_.size());
  {
    std::size_t h = 0;
    hit_cursor_.assign(hit_start_.begin(), hit_start_.end() - 1);
    for (std::uint32_t u = 0; u < end_keys.size(); ++u) {
      if (!is_hit[u]) continue;
      const std::uint32_t b = hit_block_[h++];
      hit_list_[hit_cursor_[b]++] = u;
      const int l = local_index(end_keys[u]);
      merged_hit_[b][l >> 6] |= std::uint64_t{1} << (l & 63);
    }
  }
  const auto& merged_keys = merged_.keys();
  order_.resize(merged_keys.size());
  for (std::uint32_t b = 0; b < order_.size(); ++b) order_[b] = b;
  std::sort(order_.begin(), order_.end(),
            [&](std::uint32_t a, std::uint32_t b) { return merged_keys[a] < merged_keys[b]; });
  auto& blocks = map.blocks();
  const std::size_t blocks_before = blocks.block_count();
  block_of_index_.resize(merged_keys.size());
  for (std::uint32_t b : order_) block_of_index_[b] = &blocks.find_or_create(unpack_block(merged_keys[b]));
  stats.blocks_created += blocks.block_count() - blocks_before;
  for (std::size_t b = 0; b < merged_keys.size(); ++b) {
    for (std::size_t w = 0; w < BlockMask{}.size(); ++w) {
      stats.misses += static_cast<std::size_t>(std::popcount(merged_miss_[b][w] & ~merged_hit_[b][w]));
    }
  }
  stats.hits += hit_list_.size();
  // Each block gets the storage pass 4 writes into: its log-odds expanded
  // unless uniform and left as they are (misses only, on voxels at the
  // clamp minimum), room for a row per hit voxel without evidence yet.
  const OccupancyModel& occ = map.occupancy();
  for (std::size_t b = 0; b < merged_keys.size(); ++b) {
    SemanticBlock& block = *block_of_index_[b];
    std::size_t new_rows = 0;
    for (std::size_t h = hit_start_[b]; h != hit_start_[b + 1]; ++h) {
      new_rows += block.holds_evidence(local_index(end_keys[hit_list_[h]])) ? 0 : 1;
    }
    const bool hits = hit_start_[b + 1] != hit_start_[b];
    const std::int16_t u = block.uniform_log_odds();
    blocks.prepare(block, hits || occ.add(u, occ.miss()) != u, new_rows);
  }

  // Pass 4: parallel updates, one block per task (its misses, then its
  // hits), so each voxel belongs to exactly one task.
  const LabelFusion& fusion = map.fusion();
  const std::vector<ClassObservation>& observations = rays.ends().observations();
  uniform_after_.assign(merged_keys.size(), 0);
  const kernels::LogOddsMiss miss_update{occ.miss(), occ.min(), occ.max(), occ.threshold()};
  const kernels::SimdLevel level = kernels::active_simd_level();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, merged_keys.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t b = range.begin(); b != range.end(); ++b) {
                        update_block(*block_of_index_[b], merged_miss_[b], merged_hit_[b], b, occ,
                                     miss_update, level, fusion, end_keys, observations);
                        uniform_after_[b] = SemanticBlocks::uniform_slab(*block_of_index_[b]) ? 1 : 0;
                      }
                    });
  // Blocks whose log-odds all became equal give their slab back, and rows
  // storage well beyond what is left.
  for (std::size_t b = 0; b < merged_keys.size(); ++b)
    blocks.settle(*block_of_index_[b], uniform_after_[b] != 0);
}

void ScanUpdate::update_block(SemanticBlock& block, const BlockMask& miss, const BlockMask& hit,
                              std::size_t b, const OccupancyModel& occ,
                              const kernels::LogOddsMiss& miss_update, kernels::SimdLevel level,
                              const LabelFusion& fusion,
                              const std::vector<VoxelKey>& end_keys,
                              const std::vector<ClassObservation>& observations) const {
  std::int8_t* log_odds = block.log_odds_slab();
  BlockMask missed, free;
  for (std::size_t w = 0; w < miss.size(); ++w) missed[w] = miss[w] & ~hit[w];
  if (log_odds != nullptr) {
    kernels::apply_log_odds_misses(log_odds, missed.data(), miss_update, free.data(), level);
  } else {
    // Not expanded: uniform at the clamp minimum, which the misses leave so
    // (prepare()), and free.
    free = occ.state(block.uniform_log_odds()) == VoxelState::Free ? missed : BlockMask{};
  }
  // A voxel left free loses some of its class evidence (few hold any).
  for (std::size_t w = 0; w < miss.size(); ++w) {
    for (std::uint64_t bits = free[w] & block.evidence_mask()[w]; bits != 0; bits &= bits - 1) {
      const int l = static_cast<int>(w * 64) + std::countr_zero(bits);
      block.change_evidence(l, [&](ClassEvidence& evidence) { fusion.decay(evidence); });
    }
  }
  for (std::size_t h = hit_start_[b]; h != hit_start_[b + 1]; ++h) {
    const std::uint32_t u = hit_list_[h];
    const int l = local_index(end_keys[u]);
    log_odds[l] = stored_log_odds(occ.add(log_odds_of(log_odds[l]), occ.hit()));
    block.change_evidence(l, [&](ClassEvidence& evidence) { fusion.observe(evidence, observations[u]); });
  }
}

}  // namespace sarmap::metric
