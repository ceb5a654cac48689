#include "engine/metric/scan_update.hpp"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <span>

#include <tbb/task_group.h>

#include "engine/core/capacity_bytes.hpp"
#include "engine/metric/grid_hit_list.hpp"
#include "kernels/log_odds_misses.hpp"

namespace sarmap::metric {

static_assert(kernels::kUnknownLogOddsByte == kStoredUnknownLogOdds &&
                  kernels::kLogOddsBlockVoxels == kBlockVoxels &&
                  kernels::kLogOddsBlockWords == BlockMask{}.size(),
              "the miss kernel reads a block's slab as the map stores it");

namespace {

// What every block's pass 4 reads of the map and of the scan.
struct BlockUpdateInputs {
  const OccupancyModel& occ;
  kernels::LogOddsMiss miss_update;
  kernels::SimdLevel level;
  const LabelFusion& fusion;
  std::span<const VoxelKey> end_keys;
  std::span<const ClassObservation> observations;
  std::span<const std::uint32_t> hits;  // end indices, a block's in its HitRange
};

// Pass 4 for one block: its misses (where not hit), then its hits. Returns
// the voxels updated as free.
std::size_t update_block(SemanticBlock& block, const BlockMask& miss, ScanUpdate::HitRange range,
                         const BlockUpdateInputs& in) {
  BlockMask hit{};
  for (std::uint32_t h = range.begin; h != range.end; ++h) {
    const int l = local_index(in.end_keys[in.hits[h]]);
    hit[l >> 6] |= std::uint64_t{1} << (l & 63);
  }
  BlockMask missed, free;
  std::size_t misses = 0;
  for (std::size_t w = 0; w < miss.size(); ++w) {
    missed[w] = miss[w] & ~hit[w];
    misses += static_cast<std::size_t>(std::popcount(missed[w]));
  }
  std::int8_t* log_odds = block.log_odds_slab();
  if (log_odds != nullptr) {
    kernels::apply_log_odds_misses(log_odds, missed.data(), in.miss_update, free.data(), in.level);
  } else {
    // Not expanded: uniform at the clamp minimum, which the misses leave so
    // (prepare()), and free.
    free = in.occ.state(block.uniform_log_odds()) == VoxelState::Free ? missed : BlockMask{};
  }
  // A voxel left free loses some of its class evidence (few hold any).
  for (std::size_t w = 0; w < miss.size(); ++w) {
    for (std::uint64_t bits = free[w] & block.evidence_mask()[w]; bits != 0; bits &= bits - 1) {
      const int l = static_cast<int>(w * 64) + std::countr_zero(bits);
      block.change_evidence(l, [&](ClassEvidence& evidence) { in.fusion.decay(evidence); });
    }
  }
  for (std::uint32_t h = range.begin; h != range.end; ++h) {
    const std::uint32_t u = in.hits[h];
    const int l = local_index(in.end_keys[u]);
    log_odds[l] = stored_log_odds(in.occ.add(log_odds_of(log_odds[l]), in.occ.hit()));
    block.change_evidence(l, [&](ClassEvidence& evidence) { in.fusion.observe(evidence, in.observations[u]); });
  }
  return misses;
}

// Pass 3's last step for one block: the storage pass 4 writes into, its
// log-odds expanded unless uniform and left as they are (misses only, on
// voxels at the clamp minimum), and room for a row per hit voxel without
// evidence yet.
void prepare_block(SemanticBlocks& blocks, SemanticBlock& block, ScanUpdate::HitRange range,
                   std::span<const std::uint32_t> hits, std::span<const VoxelKey> end_keys,
                   const OccupancyModel& occ) {
  std::size_t new_rows = 0;
  for (std::uint32_t h = range.begin; h != range.end; ++h) {
    new_rows += block.holds_evidence(local_index(end_keys[hits[h]])) ? 0 : 1;
  }
  const std::int16_t u = block.uniform_log_odds();
  blocks.prepare(block, range.begin != range.end || occ.add(u, occ.miss()) != u, new_rows);
}

// The blocks of the threads' dense grids over box that some ray crossed or
// ended in, in grid order, each with its misses (the grids' words ORed, and
// cleared once read, so the grids are all zero again) and its hits where
// they are listed by grid block: on_block(packed key, misses, hits).
template <class OnBlock>
void merge_dense_grids(std::span<std::uint64_t* const> grids, const kernels::DenseMaskGrid& box,
                       const GridHitList& grid_hits, OnBlock&& on_block) {
  std::size_t g = 0;
  for (std::int32_t k = 0; k < box.blocks[2]; ++k) {
    for (std::int32_t j = 0; j < box.blocks[1]; ++j) {
      for (std::int32_t i = 0; i < box.blocks[0]; ++i, ++g) {
        BlockMask m{};
        for (std::uint64_t* grid : grids) {
          std::uint64_t* words = grid + g * m.size();
          std::uint64_t any = 0;
          for (std::size_t w = 0; w < m.size(); ++w) any |= words[w];
          if (any == 0) continue;
          for (std::size_t w = 0; w < m.size(); ++w) m[w] |= words[w];
          std::fill(words, words + m.size(), 0);
        }
        std::uint64_t any = 0;
        for (std::uint64_t w : m) any |= w;
        ScanUpdate::HitRange hits;
        if (grid_hits.listed()) hits = {grid_hits.begin(g), grid_hits.begin(g + 1)};
        if (any == 0 && hits.begin == hits.end) continue;
        on_block(pack(box.first_block[0] + i, box.first_block[1] + j, box.first_block[2] + k), m, hits);
      }
    }
  }
}

}  // namespace

std::uint32_t ScanUpdate::merged_index(std::uint64_t packed_block) {
  const std::uint32_t b = merged_.find_or_insert(packed_block);
  if (b == merged_miss_.size()) {
    merged_miss_.emplace_back();
    hit_range_.emplace_back();
  }
  return b;
}

std::size_t ScanUpdate::memory_bytes() const {
  return merged_.memory_bytes() + capacity_bytes(merged_miss_) + capacity_bytes(hit_range_) +
         capacity_bytes(dense_grids_) + capacity_bytes(order_) + capacity_bytes(batches_) +
         batches_.size() * sizeof(UpdateBatch) + capacity_bytes(hit_list_) + capacity_bytes(hit_block_) +
         capacity_bytes(hit_start_);
}

ScanUpdate::UpdateBatch& ScanUpdate::open_batch() {
  if (batches_in_use_ > 0 && batches_[batches_in_use_ - 1]->size < kUpdateBatch) {
    return *batches_[batches_in_use_ - 1];
  }
  if (batches_in_use_ == batches_.size()) batches_.push_back(std::make_unique<UpdateBatch>());
  UpdateBatch& batch = *batches_[batches_in_use_++];
  batch.size = 0;
  return batch;
}

void ScanUpdate::list_hits_by_merged_block(std::span<const VoxelKey> end_keys,
                                           std::span<const std::uint8_t> is_hit) {
  hit_block_.clear();
  for (std::uint32_t u = 0; u < end_keys.size(); ++u) {
    if (is_hit[u]) hit_block_.push_back(merged_index(pack(block_of(end_keys[u]))));  // created if no ray crossed it
  }
  sort_hits_by_block(is_hit, hit_block_, merged_miss_.size(), hit_start_, hit_list_);
  for (std::size_t b = 0; b < hit_range_.size(); ++b) hit_range_[b] = {hit_start_[b], hit_start_[b + 1]};
}

void ScanUpdate::apply(MetricMap& map, ScanRays& rays, IntegrationStats& stats) {
  // Pass 3: merge, find each block's hits, create blocks in sorted order.
  merged_.clear();
  merged_miss_.clear();
  hit_range_.clear();
  batches_in_use_ = 0;
  for (const ThreadMisses& t : rays.threads()) {
    const auto& keys = t.blocks.keys();
    for (std::size_t b = 0; b < keys.size(); ++b) {
      BlockMask& m = merged_miss_[merged_index(keys[b])];
      for (std::size_t w = 0; w < m.size(); ++w) m[w] |= t.miss[b][w];
    }
  }
  const GridHitList& grid_hits = rays.hits_by_grid_block();
  const auto& box = rays.dense_box();
  dense_grids_.clear();
  if (box) {
    for (ThreadMisses& t : rays.threads()) {
      if (t.dense_in_use) dense_grids_.push_back(t.dense.data());
    }
  }
  // The grids' blocks come in sorted key order (pack() orders by z, then y,
  // then x, as the grid runs): when they are all the scan's blocks and their
  // hits are listed, the batches are handed out as the grids' merge goes.
  const bool grid_in_key_order = box && grid_hits.listed() && merged_.size() == 0;
  if (box && !grid_in_key_order) {
    const auto merge_block = [&](std::uint64_t key, const BlockMask& m, HitRange hits) {
      const std::uint32_t b = merged_index(key);
      for (std::size_t w = 0; w < m.size(); ++w) merged_miss_[b][w] |= m[w];
      hit_range_[b] = hits;
    };
    merge_dense_grids(dense_grids_, *box, grid_hits, merge_block);
    rays.dense_grids_cleared();
  }
  const std::span<const VoxelKey> end_keys = rays.ends().keys();
  std::span<const std::uint32_t> hits = grid_hits.hits();
  if (!grid_hits.listed()) {
    list_hits_by_merged_block(end_keys, rays.end_is_hit());
    hits = hit_list_;
  }
  auto& blocks = map.blocks();
  const std::size_t blocks_before = blocks.block_count();
  const OccupancyModel& occ = map.occupancy();
  const BlockUpdateInputs inputs{occ,
                                 {occ.miss(), occ.min(), occ.max(), occ.threshold()},
                                 kernels::active_simd_level(),
                                 map.fusion(),
                                 end_keys,
                                 rays.ends().observations(),
                                 hits};
  // The blocks are found or created in sorted key order and prepared a
  // batch at a time by this thread, serially (both change the map's
  // storage), while pass 4 updates the batches already prepared: the other
  // threads work instead of waiting for the whole of pass 3. A block's
  // record and storage do not move while later blocks are created and
  // prepared (BlockMap, SemanticBlocks), and each block's update reads and
  // writes that block only, so the map is the same as with the passes one
  // after the other.
  tbb::task_group updating;
  const auto hand_out = [&](UpdateBatch& batch) {
    for (std::size_t n = 0; n < batch.size; ++n) {
      SemanticBlock& block = blocks.find_or_create(unpack_block(batch.key[n]));
      batch.block[n] = &block;
      prepare_block(blocks, block, batch.hits[n], hits, end_keys, occ);
    }
    // Pass 4 for the batch, in a task: each block (its misses, then its
    // hits) by one thread, so each voxel is written once.
    updating.run([&inputs, &batch] {
      for (std::size_t n = 0; n < batch.size; ++n) {
        SemanticBlock& block = *batch.block[n];
        const std::size_t misses = update_block(block, batch.miss[n], batch.hits[n], inputs);
        batch.misses[n] = static_cast<std::uint32_t>(misses);
        batch.uniform_after[n] = SemanticBlocks::uniform_slab(block) ? 1 : 0;
      }
    });
  };
  const auto add_block = [&](std::uint64_t key, const BlockMask& misses, HitRange block_hits) {
    UpdateBatch& batch = open_batch();
    batch.key[batch.size] = key;
    batch.miss[batch.size] = misses;
    batch.hits[batch.size] = block_hits;
    if (++batch.size == kUpdateBatch) hand_out(batch);
  };
  try {
    if (grid_in_key_order) {
      merge_dense_grids(dense_grids_, *box, grid_hits, add_block);
      rays.dense_grids_cleared();
    } else {
      const auto& merged_keys = merged_.keys();
      order_.resize(merged_keys.size());
      for (std::uint32_t b = 0; b < order_.size(); ++b) order_[b] = b;
      std::sort(order_.begin(), order_.end(),
                [&](std::uint32_t a, std::uint32_t b) { return merged_keys[a] < merged_keys[b]; });
      for (const std::uint32_t b : order_) add_block(merged_keys[b], merged_miss_[b], hit_range_[b]);
    }
    if (batches_in_use_ > 0 && batches_[batches_in_use_ - 1]->size < kUpdateBatch) {
      hand_out(*batches_[batches_in_use_ - 1]);
    }
  } catch (...) {
    updating.wait();  // the tasks read this frame's locals
    throw;
  }
  updating.wait();
  stats.blocks_created += blocks.block_count() - blocks_before;
  stats.hits += hits.size();
  // Blocks whose log-odds all became equal give their slab back, and rows
  // storage well beyond what is left.
  for (std::size_t i = 0; i < batches_in_use_; ++i) {
    const UpdateBatch& batch = *batches_[i];
    for (std::size_t n = 0; n < batch.size; ++n) {
      stats.misses += batch.misses[n];
      blocks.settle(*batch.block[n], batch.uniform_after[n] != 0);
    }
  }
}

}  // namespace sarmap::metric
