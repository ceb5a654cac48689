// Writes one scan's rays (scan_rays.hpp) into the map: the last two passes
// of ray integration. Pass 3, serial: the threads' miss masks merged by OR
// (so the union does not depend on which thread walked which ray), each
// block's hits found in the list ScanRays made by grid block (or listed here
// when it made none), and the blocks found or created in sorted key order,
// and each given the storage pass 4 writes into (SemanticBlocks::prepare).
// Pass 4, parallel: each block by one thread, its misses (hits override
// them) and then its hits, so every voxel is written once; a batch of blocks
// starts as soon as pass 3 has prepared it, and in the common case (a dense
// walk, its hits listed by grid block) pass 3 merges the grids a batch at a
// time too. Then, serially, blocks whose log-odds became uniform collapse
// (settle).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/flat_key_index.hpp"
#include "engine/metric/integration_settings.hpp"
#include "engine/metric/metric_map.hpp"
#include "engine/metric/scan_rays.hpp"
#include "kernels/log_odds_misses.hpp"

namespace sarmap::metric {

class ScanUpdate {
 public:
  // Applies rays to map; adds hits, misses and blocks_created to stats.
  // Clears the rays' dense miss grids as it reads them (ScanRays keeps them
  // zero between scans). Parallel over the calling thread's oneTBB arena;
  // the map does not depend on its thread count.
  void apply(MetricMap& map, ScanRays& rays, IntegrationStats& stats);
  // Bytes held between scans (every table and list, by capacity).
  std::size_t memory_bytes() const;

  // A merged block's hits: hits[begin .. end) of the scan's hit list.
  struct HitRange {
    std::uint32_t begin = 0, end = 0;
  };

 private:
  // Blocks prepared (pass 3) before their updates (pass 4) are handed out
  // as a task: several tasks per thread even in a scan of a hundred blocks.
  static constexpr std::size_t kUpdateBatch = 16;

  // Up to kUpdateBatch blocks in sorted key order: pass 3 fills and prepares
  // them, then one task runs pass 4 on them. Each batch is an allocation of
  // its own, so a task's batch stays where it is while pass 3 fills more.
  struct UpdateBatch {
    std::size_t size = 0;
    std::array<std::uint64_t, kUpdateBatch> key;  // packed block keys
    std::array<BlockMask, kUpdateBatch> miss;
    std::array<HitRange, kUpdateBatch> hits;
    std::array<SemanticBlock*, kUpdateBatch> block;
    std::array<std::uint32_t, kUpdateBatch> misses;        // pass 4: voxels updated as free
    std::array<std::uint8_t, kUpdateBatch> uniform_after;  // pass 4: its log-odds all equal
  };

  // Index of a block among the scan's merged blocks (created with no misses
  // and no hits).
  std::uint32_t merged_index(std::uint64_t packed_block);
  // The hits listed by merged block (hit_list_, hit_range_), for scans whose
  // rays did not list them by grid block.
  void list_hits_by_merged_block(std::span<const VoxelKey> end_keys, std::span<const std::uint8_t> is_hit);
  // The batch being filled (a new one when the last is full).
  UpdateBatch& open_batch();

  FlatKeyIndex merged_{16384};
  std::vector<BlockMask> merged_miss_;  // per merged block
  std::vector<HitRange> hit_range_;     // per merged block
  std::vector<std::uint64_t*> dense_grids_;  // the threads' grids in use
  std::vector<std::uint32_t> order_;         // merged blocks in sorted key order
  std::vector<std::unique_ptr<UpdateBatch>> batches_;  // kept between scans
  std::size_t batches_in_use_ = 0;
  // list_hits_by_merged_block(): the hits in merged block order
  // (sort_hits_by_block of each hit's block, hit_block_, into hit_start_).
  std::vector<std::uint32_t> hit_list_, hit_block_, hit_start_;
};

}  // namespace sarmap::metric
