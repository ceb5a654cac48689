#include "engine/metric/voxel_cloud.hpp"

#include "engine/core/class_colors.hpp"

namespace sarmap::metric {

PointBuffer occupied_voxel_cloud(const MetricMap& map) {
  PointBuffer cloud;
  cloud.enable_labels();
  const OccupancyModel& occ = map.occupancy();
  for (const BlockKey& bk : map.blocks().sorted_block_keys()) {
    const auto& block = *map.blocks().find(bk);
    for (int l = 0; l < kBlockVoxels; ++l) {
      const SemanticVoxel& v = block.voxels[l];
      if (occ.state(v.log_odds) != VoxelState::Occupied) continue;
      const Eigen::Vector3d c = map.center_of(voxel_of(bk, l));
      cloud.push_back(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()));
      cloud.labels()[cloud.size() - 1] = static_cast<std::uint8_t>(LabelFusion::dominant(v.evidence));
    }
  }
  paint_class_colors(cloud);
  return cloud;
}

}  // namespace sarmap::metric
