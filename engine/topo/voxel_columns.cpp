#include "engine/topo/voxel_columns.hpp"

#include <algorithm>

namespace sarmap::topo {

VoxelColumns voxel_columns(const metric::MetricMap& map) {
  struct Occupied {
    std::int32_t x, y, z;
    ClassId label;
  };
  std::vector<Occupied> found;
  const metric::OccupancyModel& occupancy = map.occupancy();
  map.blocks().for_each_block([&](const metric::BlockKey& key, const metric::MetricMap::Blocks::Block& block) {
    for (int local = 0; local < metric::kBlockVoxels; ++local) {
      const metric::SemanticVoxel& v = block.voxels[local];
      if (occupancy.state(v.log_odds) != metric::VoxelState::Occupied) continue;
      const metric::VoxelKey k = metric::voxel_of(key, local);
      found.push_back({k.x, k.y, k.z, metric::LabelFusion::dominant(v.evidence)});
    }
  });
  VoxelColumns out;
  out.resolution = map.resolution();
  if (found.empty()) return out;
  std::int32_t x1 = found.front().x, y1 = found.front().y;
  out.x0 = x1;
  out.y0 = y1;
  for (const Occupied& o : found) {
    out.x0 = std::min(out.x0, o.x);
    out.y0 = std::min(out.y0, o.y);
    x1 = std::max(x1, o.x);
    y1 = std::max(y1, o.y);
  }
  out.width = x1 - out.x0 + 1;
  out.height = y1 - out.y0 + 1;
  out.start.assign(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height) + 1, 0);
  for (const Occupied& o : found) ++out.start[out.column(o.x - out.x0, o.y - out.y0) + 1];
  for (std::size_t c = 1; c < out.start.size(); ++c) out.start[c] += out.start[c - 1];
  std::vector<std::uint32_t> fill(out.start.begin(), out.start.end() - 1);
  out.z.resize(found.size());
  out.label.resize(found.size());
  for (const Occupied& o : found) {
    const std::uint32_t at = fill[out.column(o.x - out.x0, o.y - out.y0)]++;
    out.z[at] = o.z;
    out.label[at] = o.label;
  }
  // Each column's few voxels into height order (insertion sort: short runs).
  for (std::size_t c = 0; c + 1 < out.start.size(); ++c) {
    for (std::uint32_t i = out.start[c] + 1; i < out.start[c + 1]; ++i) {
      for (std::uint32_t k = i; k > out.start[c] && out.z[k - 1] > out.z[k]; --k) {
        std::swap(out.z[k - 1], out.z[k]);
        std::swap(out.label[k - 1], out.label[k]);
      }
    }
  }
  return out;
}

}  // namespace sarmap::topo
