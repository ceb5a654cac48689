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

// A counting sort by column, then each column's few voxels into height order.
template <class Range>
VoxelColumns by_column(const Range& found, std::size_t count, double resolution) {
  VoxelColumns out;
  out.resolution = resolution;
  if (count == 0) return out;
  bool first = true;
  std::int32_t x1 = 0, y1 = 0;
  for (const auto& o : found) {
    if (first) {
      out.x0 = x1 = o.x;
      out.y0 = y1 = o.y;
      first = false;
    }
    out.x0 = std::min(out.x0, o.x);
    out.y0 = std::min(out.y0, o.y);
    x1 = std::max(x1, o.x);
    y1 = std::max(y1, o.y);
  }
  out.width = x1 - out.x0 + 1;
  out.height = y1 - out.y0 + 1;
  out.start.assign(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height) + 1, 0);
  for (const auto& o : found) ++out.start[out.column(o.x - out.x0, o.y - out.y0) + 1];
  for (std::size_t c = 1; c < out.start.size(); ++c) out.start[c] += out.start[c - 1];
  std::vector<std::uint32_t> fill(out.start.begin(), out.start.end() - 1);
  out.z.resize(count);
  out.label.resize(count);
  for (const auto& o : found) {
    const std::uint32_t at = fill[out.column(o.x - out.x0, o.y - out.y0)]++;
    out.z[at] = o.z;
    out.label[at] = o.label;
  }
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

// Every voxel of every cached block, as one range for by_column.
template <class Blocks>
struct AllVoxels {
  const Blocks& blocks;
  struct Iterator {
    typename Blocks::const_iterator block, end;
    std::size_t i;
    const auto& operator*() const { return block->second[i]; }
    Iterator& operator++() {
      if (++i == block->second.size()) {
        i = 0;
        do ++block;
        while (block != end && block->second.empty());
      }
      return *this;
    }
    bool operator!=(const Iterator& o) const { return block != o.block || i != o.i; }
  };
  Iterator begin() const {
    auto b = blocks.begin();
    while (b != blocks.end() && b->second.empty()) ++b;
    return {b, blocks.end(), 0};
  }
  Iterator end() const { return {blocks.end(), blocks.end(), 0}; }
};

}  // namespace

VoxelColumns voxel_columns(const metric::MetricMap& map) {
  std::vector<Occupied> found;
  map.blocks().for_each_block([&](const metric::BlockKey& key, const metric::MetricMap::Blocks::Block& block) {
    for_each_occupied(map, key, block, [&](const Occupied& o) { found.push_back(o); });
  });
  return by_column(found, found.size(), map.resolution());
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
  std::size_t count = 0;
  for (const auto& entry : blocks_) count += entry.second.size();
  return by_column(AllVoxels<decltype(blocks_)>{blocks_}, count, resolution);
}

}  // namespace sarmap::topo
