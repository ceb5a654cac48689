#include "engine/metric/map_summary.hpp"

#include <cstdint>
#include <optional>
#include <unordered_map>

namespace sarmap::metric {

namespace {

// A block's value when it is uniform without evidence, else nullopt.
std::optional<std::int16_t> uniform_value(const MetricMap::Blocks::Block& block) {
  if (!block.uniform_occupancy() || block.row_count() != 0) return std::nullopt;
  return block.uniform_log_odds();
}

// The uniform blocks, and those of them in complete aligned 2 x 2 x 2
// groups of one value: a pass over the blocks, not their voxels.
void count_uniform_blocks(const MetricMap& map, MapSummary& s) {
  struct Group {
    int blocks = 0;
    std::int16_t value = 0;
    bool uniform = true;
  };
  std::unordered_map<std::uint64_t, Group> groups;
  map.blocks().for_each_block([&](const BlockKey& bk, const MetricMap::Blocks::Block& block) {
    // Arithmetic shifts: the group of block -1 is -1, of blocks -2 and -1 alike.
    Group& g = groups[pack(BlockKey{bk.x >> 1, bk.y >> 1, bk.z >> 1})];
    const std::optional<std::int16_t> value = uniform_value(block);
    if (value) ++s.uniform_blocks;
    if (!value || (g.blocks > 0 && *value != g.value)) g.uniform = false;
    if (value) g.value = *value;
    ++g.blocks;
  });
  for (const auto& [key, g] : groups) {
    if (g.uniform && g.blocks == 8) s.blocks_in_uniform_groups += 8;
  }
}

}  // namespace

MapSummary summarize_map(const MetricMap& map) {
  MapSummary s;
  s.counts.blocks = map.blocks().block_count();
  count_uniform_blocks(map, s);
  const OccupancyModel& occ = map.occupancy();
  const double half = 0.5 * map.resolution();
  map.blocks().for_each_block([&](const BlockKey& bk, const MetricMap::Blocks::Block& block) {
    for (int l = 0; l < kBlockVoxels; ++l) {
      const SemanticVoxel v = block.voxel(l);
      const VoxelState state = occ.state(v.log_odds);
      if (state == VoxelState::Unknown) continue;
      const Eigen::Vector3d c = map.center_of(voxel_of(bk, l));
      const Eigen::Vector3d lo = c.array() - half, hi = c.array() + half;
      s.known_bounds.extend(lo);
      s.known_bounds.extend(hi);
      if (state == VoxelState::Free) {
        ++s.counts.free;
        continue;
      }
      ++s.counts.occupied;
      ++s.occupied_by_class[static_cast<std::size_t>(LabelFusion::dominant(v.evidence))];
      s.occupied_bounds.extend(lo);
      s.occupied_bounds.extend(hi);
    }
  });
  s.counts.known = s.counts.free + s.counts.occupied;
  return s;
}

}  // namespace sarmap::metric
