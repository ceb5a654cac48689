#include "engine/metric/voxel_cloud.hpp"

#include <charconv>

#include "engine/core/class_colors.hpp"
#include "engine/io/point_cloud_file.hpp"

namespace sarmap::metric {

PointBuffer occupied_voxel_cloud(const MetricMap& map) {
  PointBuffer cloud;
  cloud.enable_labels();
  const std::size_t probability = cloud.add_score("probability");
  const OccupancyModel& occ = map.occupancy();
  for (const BlockKey& bk : map.blocks().sorted_block_keys()) {
    const auto& block = *map.blocks().find(bk);
    for (int l = 0; l < kBlockVoxels; ++l) {
      const SemanticVoxel& v = block.voxels[l];
      if (occ.state(v.log_odds) != VoxelState::Occupied) continue;
      const Eigen::Vector3d c = map.center_of(voxel_of(bk, l));
      cloud.push_back(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()));
      const std::size_t i = cloud.size() - 1;
      cloud.labels()[i] = static_cast<std::uint8_t>(LabelFusion::dominant(v.evidence));
      cloud.score(probability)[i] = static_cast<float>(OccupancyModel::probability(v.log_odds));
    }
  }
  paint_class_colors(cloud);
  return cloud;
}

std::string voxel_size_comment(const MetricMap& map) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, map.resolution()).ptr;
  return "voxel_size " + std::string(text, end);
}

void write_voxel_cloud(const MetricMap& map, const std::filesystem::path& path, bool binary) {
  PointCloudWriteOptions options;
  options.binary = binary;
  options.comments = {voxel_size_comment(map)};
  write_point_cloud(path, occupied_voxel_cloud(map), options);
}

}  // namespace sarmap::metric
