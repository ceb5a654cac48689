#include "engine/metric/voxel_cloud.hpp"

namespace sarmap::metric {

PointBuffer occupied_voxel_cloud(const MetricMap& map) {
  PointBuffer cloud;
  cloud.enable_labels();
  cloud.enable_colors();
  const OccupancyModel& occ = map.occupancy();
  for (const BlockKey& bk : map.blocks().sorted_block_keys()) {
    const auto& block = *map.blocks().find(bk);
    for (int l = 0; l < kBlockVoxels; ++l) {
      const SemanticVoxel& v = block.voxels[l];
      if (occ.state(v.log_odds) != VoxelState::Occupied) continue;
      const Eigen::Vector3d c = map.center_of(voxel_of(bk, l));
      cloud.push_back(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()));
      const ClassId id = LabelFusion::dominant(v.evidence);
      const std::size_t i = cloud.size() - 1;
      cloud.labels()[i] = static_cast<std::uint8_t>(id);
      cloud.red()[i] = class_info(id).color.r;
      cloud.green()[i] = class_info(id).color.g;
      cloud.blue()[i] = class_info(id).color.b;
    }
  }
  return cloud;
}

}  // namespace sarmap::metric
