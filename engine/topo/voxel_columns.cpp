#include "engine/topo/voxel_columns.hpp"

#include <algorithm>

namespace sarmap::topo {
namespace {

struct Occupied {
  std::int32_t x, y, z;
  ClassId label;
};

template <class Fn>
void for_each_occupied(const metric::MetricMap& map, const metric::BlockKey& key,
                       const metric::MetricMap::Blocks::Block& block, Fn&& fn) {
  const metric::OccupancyModel& occupancy = map.occupancy();
  // A block of one log-odds for all (unknown, or free space) holds nothing occupied, mostly.
  if (block.uniform_occupancy() && occupancy.state(block.uniform_log_odds()) != metric::VoxelState::Occupied)
    return;
  for (int local = 0; local < metric::kBlockVoxels; ++local) {
    if (occupancy.state(block.log_odds(local)) != metric::VoxelState::Occupied) continue;
    const metric::VoxelKey k = metric::voxel_of(key, local);
    fn(Occupied{k.x, k.y, k.z, metric::LabelFusion::dominant(block.evidence(local))});
  }
}

// A counting sort by column, then each column's few voxels into height order
// (nothing to move when `for_each_voxel` visits each column bottom-up).
template <class ForEachVoxel>
VoxelColumns by_column(ForEachVoxel&& for_each_voxel, std::size_t count, double resolution) {
  VoxelColumns out;
  out.resolution = resolution;
  if (count == 0) return out;
  bool first = true;
  std::int32_t x1 = 0, y1 = 0;
  for_each_voxel([&](const auto& o) {
    if (first) {
      out.x0 = x1 = o.x;
      out.y0 = y1 = o.y;
      first = false;
    }
    out.x0 = std::min(out.x0, o.x);
    out.y0 = std::min(out.y0, o.y);
    x1 = std::max(x1, o.x);
    y1 = std::max(y1, o.y);
  });
  out.width = x1 - out.x0 + 1;
  out.height = y1 - out.y0 + 1;
  out.start.assign(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height) + 1, 0);
  for_each_voxel([&](const auto& o) { ++out.start[out.column(o.x - out.x0, o.y - out.y0) + 1]; });
  for (std::size_t c = 1; c < out.start.size(); ++c) out.start[c] += out.start[c - 1];
  std::vector<std::uint32_t> fill(out.start.begin(), out.start.end() - 1);
  out.z.resize(count);
  out.label.resize(count);
  for_each_voxel([&](const auto& o) {
    const std::uint32_t at = fill[out.column(o.x - out.x0, o.y - out.y0)]++;
    out.z[at] = o.z;
    out.label[at] = o.label;
  });
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

}  // namespace

VoxelColumns voxel_columns(const metric::MetricMap& map) {
  std::vector<Occupied> found;
  map.blocks().for_each_block([&](const metric::BlockKey& key, const metric::MetricMap::Blocks::Block& block) {
    for_each_occupied(map, key, block, [&](const Occupied& o) { found.push_back(o); });
  });
  return by_column([&found](auto&& fn) { std::for_each(found.begin(), found.end(), fn); }, found.size(),
                   map.resolution());
}

void OccupiedVoxelCache::refresh(const metric::MetricMap& map, const Bounds* changed) {
  std::erase_if(blocks_, [&map](const auto& entry) { return map.blocks().find(metric::unpack_block(entry.first)) == nullptr; });
  const double edge = map.resolution() * metric::kBlockEdge;
  map.blocks().for_each_block([&](const metric::BlockKey& key, const metric::MetricMap::Blocks::Block& block) {
    if (changed != nullptr) {
      const Eigen::Vector3d lo(key.x * edge, key.y * edge, key.z * edge);
      const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(edge);
      if ((hi.array() < changed->min.array()).any() || (lo.array() > changed->max.array()).any()) return;
    }
    std::vector<Voxel>& voxels = blocks_[metric::pack(key)];
    voxels.clear();
    for_each_occupied(map, key, block, [&](const Occupied& o) { voxels.push_back({o.x, o.y, o.z, o.label}); });
  });
}

VoxelColumns OccupiedVoxelCache::columns(double resolution) const {
  // Blocks in ascending height: blocks of one column of blocks hold disjoint
  // heights, so each voxel column fills bottom-up and the output is the same
  // whatever the hash order.
  std::vector<const std::vector<Voxel>*> blocks;
  std::size_t count = 0;
  for (const auto& entry : blocks_) {
    if (entry.second.empty()) continue;
    blocks.push_back(&entry.second);
    count += entry.second.size();
  }
  std::sort(blocks.begin(), blocks.end(), [](const auto* a, const auto* b) { return a->front().z < b->front().z; });
  auto for_each_voxel = [&blocks](auto&& fn) {
    for (const std::vector<Voxel>* block : blocks) std::for_each(block->begin(), block->end(), fn);
  };
  return by_column(for_each_voxel, count, resolution);
}

}  // namespace sarmap::topo
