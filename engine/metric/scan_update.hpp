// Writes one scan's rays (scan_rays.hpp) into the map: the last two passes
// of ray integration. Pass 3, serial: the threads' miss masks merged by OR
// (so the union does not depend on which thread walked which ray), each
// block's hits found in the list ScanRays made by grid block (or listed here
// when it made none), and the blocks found or created in sorted key order,
// and each given the storage pass 4 writes into (SemanticBlocks::prepare).
// Pass 4, parallel: each block by one thread, its misses (hits override
// them) and then its hits, so every voxel is written once; a batch of blocks
// starts as soon as pass 3 has prepared it. Then, serially, blocks whose
// log-odds became uniform collapse (settle).
#pragma once

#include <cstdint>
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

  // Index of a block among the scan's merged blocks (created with no misses
  // and no hits).
  std::uint32_t merged_index(std::uint64_t packed_block);
  // The hits listed by merged block (hit_list_, hit_range_), for scans whose
  // rays did not list them by grid block.
  void list_hits_by_merged_block(const std::vector<VoxelKey>& end_keys, const std::vector<std::uint8_t>& is_hit);

  FlatKeyIndex merged_{16384};
  std::vector<BlockMask> merged_miss_;  // per merged block
  std::vector<HitRange> hit_range_;     // per merged block
  std::vector<std::uint64_t*> dense_grids_;  // the threads' grids in use
  std::vector<std::uint32_t> order_;         // merged blocks in sorted key order
  std::vector<SemanticBlock*> block_of_index_;
  std::vector<std::uint8_t> uniform_after_;     // per merged block: its log-odds all equal after pass 4
  std::vector<std::uint32_t> misses_of_block_;  // per merged block: voxels updated as free
  // list_hits_by_merged_block(): the hits in merged block order
  // (sort_hits_by_block of each hit's block, hit_block_, into hit_start_).
  std::vector<std::uint32_t> hit_list_, hit_block_, hit_start_;
};

}  // namespace sarmap::metric
