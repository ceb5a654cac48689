#include "engine/metric/voxel_cloud.hpp"

#include <charconv>

#include "engine/core/class_colors.hpp"
#include "engine/core/error.hpp"
#include "engine/io/ply_mesh.hpp"
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
      const SemanticVoxel v = block.voxel(l);
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

void write_voxel_cubes(const MetricMap& map, const std::filesystem::path& path) {
  if (point_cloud_format_of(path) != PointCloudFormat::Ply) {
    throw Error(ErrorCode::InvalidArgument, path.string() + ": voxel cubes are written as a .ply mesh");
  }
  // Corner c of a cube is at offset (c & 1, c >> 1 & 1, c >> 2 & 1) voxels
  // from its lowest corner; each face lists its corners counter-clockwise
  // seen from outside, so viewers that cull back faces show the outside.
  static constexpr std::uint32_t kFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                                 {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  const PointBuffer centres = occupied_voxel_cloud(map);
  const float half = static_cast<float>(0.5 * map.resolution());
  ColoredMesh mesh;
  mesh.comments = {voxel_size_comment(map)};
  mesh.vertices.reserve(8 * centres.size());
  mesh.vertex_colors.reserve(8 * centres.size());
  mesh.faces.reserve(6 * centres.size());
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
    const Rgb color{centres.red()[i], centres.green()[i], centres.blue()[i]};
    for (int c = 0; c < 8; ++c) {
      mesh.vertices.emplace_back(centres.x()[i] + ((c & 1) ? half : -half),
                                 centres.y()[i] + ((c & 2) ? half : -half),
                                 centres.z()[i] + ((c & 4) ? half : -half));
      mesh.vertex_colors.push_back(color);
    }
    for (const auto& face : kFaces) {
      mesh.faces.push_back({first + face[0], first + face[1], first + face[2], first + face[3]});
    }
  }
  write_ply_mesh(path, mesh);
}

}  // namespace sarmap::metric
