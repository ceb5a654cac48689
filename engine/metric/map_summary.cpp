#include "engine/metric/map_summary.hpp"

namespace sarmap::metric {

MapSummary summarize_map(const MetricMap& map) {
  MapSummary s;
  s.counts.blocks = map.blocks().block_count();
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
