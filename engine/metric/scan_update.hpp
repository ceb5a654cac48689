// Writes one scan's rays (scan_rays.hpp) into the map: the last two passes
// of ray integration. Pass 3, serial: the threads' miss masks merged by OR
// (so the union does not depend on which thread walked which ray), the hits
// as bits that override misses and listed by block, and the blocks found or
// created in sorted key order, and each given the storage pass 4 writes
// into (SemanticBlocks::prepare). Pass 4, parallel: one block per task, its
// misses and then its hits, so every voxel is written once by one thread;
// then, serially, blocks whose log-odds became uniform collapse (settle).
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

 private:
  // Index of a block among the scan's merged blocks (created empty).
  std::uint32_t merged_index(std::uint64_t packed_block);
  // Pass 4 for merged block b: its misses, then its hits.
  void update_block(SemanticBlock& block, const BlockMask& miss, const BlockMask& hit, std::size_t b,
                    const OccupancyModel& occ, const kernels::LogOddsMiss& miss_update,
                    kernels::SimdLevel level, const LabelFusion& fusion,
                    const std::vector<VoxelKey>& end_keys,
                    const std::vector<ClassObservation>& observations) const;

  FlatKeyIndex merged_{16384};
  std::vector<BlockMask> merged_miss_, merged_hit_;  // per merged block
  std::vector<std::uint64_t*> dense_grids_;          // the threads' grids in use
  std::vector<std::uint32_t> merged_of_grid_;        // per block of the dense box: merged index or kAbsent
  std::vector<std::uint32_t> order_;                 // merged blocks in sorted key order
  std::vector<SemanticBlock*> block_of_index_;
  std::vector<std::uint8_t> uniform_after_;  // per merged block: its log-odds all equal after pass 4
  // Hits (end voxels in range) by merged block: hit_list_[hit_start_[b] ..
  // hit_start_[b + 1]) are block b's; hit_block_ and hit_cursor_ build it.
  std::vector<std::uint32_t> hit_list_, hit_block_, hit_cursor_, hit_start_;
};

}  // namespace sarmap::metric
