#include "engine/topo/voxel_columns.hpp"

#include <algorithm>
#include <limits>

#include "engine/core/vector_headroom.hpp"

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

void ColumnRect::include(const ColumnRect& other) {
  if (other.empty()) return;
  if (empty()) {
    *this = other;
    return;
  }
  x0 = std::min(x0, other.x0);
  x1 = std::max(x1, other.x1);
  y0 = std::min(y0, other.y0);
  y1 = std::max(y1, other.y1);
}

void OccupiedVoxelCache::cover(std::int32_t bx0, std::int32_t bx1, std::int32_t by0, std::int32_t by1) {
  if (bwidth_ > 0) {
    bx0 = std::min(bx0, bx0_);
    by0 = std::min(by0, by0_);
    bx1 = std::max(bx1, bx0_ + bwidth_ - 1);
    by1 = std::max(by1, by0_ + bheight_ - 1);
    if (bx0 == bx0_ && by0 == by0_ && bx1 - bx0 + 1 == bwidth_ && by1 - by0 + 1 == bheight_) return;
  }
  bx0_ = bx0;
  by0_ = by0;
  bwidth_ = bx1 - bx0 + 1;
  bheight_ = by1 - by0 + 1;
  index_columns();
}

void OccupiedVoxelCache::index_columns() {
  slot_.assign(static_cast<std::size_t>(bwidth_) * static_cast<std::size_t>(bheight_), -1);
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    slot_[static_cast<std::size_t>(columns_[i].bx - bx0_) +
          static_cast<std::size_t>(bwidth_) * static_cast<std::size_t>(columns_[i].by - by0_)] =
        static_cast<std::int32_t>(i);
  }
}

void OccupiedVoxelCache::read(const metric::MetricMap& map, BlockColumn& column) {
  // Blocks bottom-up, and each block's voxels in index order (z slowest):
  // every voxel column fills in ascending height.
  std::sort(column.now.begin(), column.now.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Occupied> found;
  for (const auto& [bz, block] : column.now) {
    for_each_occupied(map, metric::BlockKey{column.bx, column.by, bz}, *block,
                      [&found](const Occupied& o) { found.push_back(o); });
  }
  const auto local = [](const Occupied& o) { return (o.x & (metric::kBlockEdge - 1)) + metric::kBlockEdge * (o.y & (metric::kBlockEdge - 1)); };
  column.start.fill(0);
  column.extent = ColumnRect();
  for (const Occupied& o : found) {
    ++column.start[local(o) + 1];
    column.extent.include({o.x, o.x, o.y, o.y});
  }
  for (int c = 1; c <= kLocalColumns; ++c) column.start[c] += column.start[c - 1];
  std::array<std::uint32_t, kLocalColumns> fill;
  std::copy(column.start.begin(), column.start.end() - 1, fill.begin());
  column.z.resize(found.size());
  column.label.resize(found.size());
  for (const Occupied& o : found) {
    const std::uint32_t at = fill[local(o)]++;
    column.z[at] = o.z;
    column.label[at] = o.label;
  }
  column.block_z.clear();
  for (const auto& entry : column.now) column.block_z.push_back(entry.first);
}

ColumnRect OccupiedVoxelCache::refresh(const metric::MetricMap& map, const Bounds* changed) {
  const auto& blocks = map.blocks();
  if (!blocks.empty()) {
    std::int32_t bx0 = std::numeric_limits<std::int32_t>::max(), by0 = bx0;
    std::int32_t bx1 = std::numeric_limits<std::int32_t>::min(), by1 = bx1;
    blocks.for_each_block([&](const metric::BlockKey& key, const Block&) {
      bx0 = std::min(bx0, key.x);
      bx1 = std::max(bx1, key.x);
      by0 = std::min(by0, key.y);
      by1 = std::max(by1, key.y);
    });
    cover(bx0, bx1, by0, by1);
  }
  const double edge = map.resolution() * metric::kBlockEdge;
  blocks.for_each_block([&](const metric::BlockKey& key, const Block& block) {
    const std::size_t at = static_cast<std::size_t>(key.x - bx0_) +
                           static_cast<std::size_t>(bwidth_) * static_cast<std::size_t>(key.y - by0_);
    if (slot_[at] < 0) {
      slot_[at] = static_cast<std::int32_t>(columns_.size());
      columns_.emplace_back();
      columns_.back().bx = key.x;
      columns_.back().by = key.y;
    }
    BlockColumn& column = columns_[static_cast<std::size_t>(slot_[at])];
    column.now.emplace_back(key.z, &block);
    if (changed == nullptr) {
      column.met = true;
    } else if (!column.met) {
      const Eigen::Vector3d lo(key.x * edge, key.y * edge, key.z * edge);
      const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(edge);
      column.met = (hi.array() >= changed->min.array()).all() && (lo.array() <= changed->max.array()).all();
    }
  });
  ColumnRect reread;
  for (BlockColumn& column : columns_) {
    // Voxels change only where a change met a block; elsewhere blocks can only be forgotten.
    const bool same_blocks = column.now.size() == column.block_z.size() &&
                             std::all_of(column.now.begin(), column.now.end(), [&column](const auto& entry) {
                               return std::binary_search(column.block_z.begin(), column.block_z.end(), entry.first);
                             });
    if (column.met || !same_blocks) {
      read(map, column);
      constexpr std::int32_t kEdge = metric::kBlockEdge;
      reread.include({column.bx * kEdge, column.bx * kEdge + kEdge - 1, column.by * kEdge, column.by * kEdge + kEdge - 1});
    }
    column.now.clear();
    column.met = false;
  }
  // Columns whose blocks the map has all forgotten (a bounded map's, with
  // --max-blocks or --keep-radius) are let go, so that the cache's memory
  // follows the map's instead of the area ever seen. Their voxels' absence
  // is in `reread` already.
  const auto forgotten = [](const BlockColumn& column) { return column.block_z.empty(); };
  if (std::any_of(columns_.begin(), columns_.end(), forgotten)) {
    std::erase_if(columns_, forgotten);
    index_columns();
  }
  return reread;
}

VoxelColumns OccupiedVoxelCache::columns(double resolution) const {
  VoxelColumns out;
  columns(resolution, out);
  return out;
}

std::size_t OccupiedVoxelCache::memory_bytes() const {
  std::size_t bytes = capacity_bytes(columns_) + capacity_bytes(slot_);
  for (const BlockColumn& c : columns_) {
    bytes += capacity_bytes(c.block_z) + capacity_bytes(c.z) + capacity_bytes(c.label) + capacity_bytes(c.now);
  }
  return bytes;
}

void OccupiedVoxelCache::columns(double resolution, VoxelColumns& out) const {
  out.resolution = resolution;
  out.x0 = out.y0 = 0;
  out.width = out.height = 0;
  out.start.clear();
  out.z.clear();
  out.label.clear();
  ColumnRect extent;
  std::size_t count = 0;
  for (const BlockColumn& column : columns_) {
    extent.include(column.extent);
    count += column.z.size();
  }
  if (count == 0) return;
  out.x0 = extent.x0;
  out.y0 = extent.y0;
  out.width = extent.x1 - extent.x0 + 1;
  out.height = extent.y1 - extent.y0 + 1;
  // Each voxel column's count at its place, then their running sum; the
  // place of every column follows from its key, whatever the order of columns_.
  assign_with_headroom(out.start, static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height) + 1,
                       std::uint32_t{0});
  const auto global = [&out](const BlockColumn& column, int c) {
    const std::int32_t x = column.bx * metric::kBlockEdge + c % metric::kBlockEdge;
    const std::int32_t y = column.by * metric::kBlockEdge + c / metric::kBlockEdge;
    return out.column(x - out.x0, y - out.y0);
  };
  for (const BlockColumn& column : columns_) {
    if (column.z.empty()) continue;
    for (int c = 0; c < kLocalColumns; ++c) {
      const std::uint32_t n = column.start[c + 1] - column.start[c];
      if (n > 0) out.start[global(column, c) + 1] = n;
    }
  }
  for (std::size_t c = 1; c < out.start.size(); ++c) out.start[c] += out.start[c - 1];
  assign_with_headroom(out.z, count, std::int32_t{0});
  assign_with_headroom(out.label, count, ClassId::Unknown);
  for (const BlockColumn& column : columns_) {
    if (column.z.empty()) continue;
    for (int c = 0; c < kLocalColumns; ++c) {
      const std::uint32_t begin = column.start[c], end = column.start[c + 1];
      if (begin == end) continue;
      const std::uint32_t at = out.start[global(column, c)];
      std::copy(column.z.begin() + begin, column.z.begin() + end, out.z.begin() + at);
      std::copy(column.label.begin() + begin, column.label.begin() + end, out.label.begin() + at);
    }
  }
}

}  // namespace sarmap::topo
