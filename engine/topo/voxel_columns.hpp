// The metric map's occupied voxels gathered by column (x, y), bottom to top,
// with their classes: what the traversability grid and the wall scene both
// read, gathered once per update in linear time (a counting sort).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/bounds.hpp"
#include "engine/core/capacity_bytes.hpp"
#include "engine/core/classes.hpp"
#include "engine/metric/metric_map.hpp"

namespace sarmap::topo {

struct VoxelColumns {
  double resolution = 0.05;
  // Voxel index of column (0, 0) and the extent, in columns.
  std::int32_t x0 = 0, y0 = 0;
  int width = 0, height = 0;
  // Column c = (x - x0) + width * (y - y0) holds entries [start[c], start[c + 1]).
  std::vector<std::uint32_t> start;
  std::vector<std::int32_t> z;  // voxel index, ascending within a column
  std::vector<ClassId> label;

  bool empty() const { return z.empty(); }
  // Bytes held, by capacity.
  std::size_t memory_bytes() const { return capacity_bytes(start) + capacity_bytes(z) + capacity_bytes(label); }
  std::size_t column(int x, int y) const { return static_cast<std::size_t>(x) + static_cast<std::size_t>(width) * y; }
};

// Deterministic whatever the hash order of the map's blocks.
VoxelColumns voxel_columns(const metric::MetricMap& map);

// Voxel columns [x0, x1] x [y0, y1], inclusive, in voxel indices; empty when
// x0 > x1.
struct ColumnRect {
  std::int32_t x0 = 0, x1 = -1, y0 = 0, y1 = -1;
  bool empty() const { return x0 > x1 || y0 > y1; }
  // Whether the two share a column.
  bool meets(const ColumnRect& other) const {
    return !empty() && !other.empty() && x0 <= other.x1 && other.x0 <= x1 && y0 <= other.y1 && other.y0 <= y1;
  }
  void include(const ColumnRect& other);
};

// The map's occupied voxels by column, kept between updates in columns of
// blocks (8 x 8 voxel columns each), so that an update re-reads only the
// columns of blocks a scan can have changed (a scan changes voxels only
// between its origin and its points), not the whole map.
class OccupiedVoxelCache {
 public:
  // Re-reads the columns of blocks that hold a block meeting `changed`
  // (every one when null) or that gained or lost a block, and returns the
  // voxel columns they cover: no voxel outside it changed.
  ColumnRect refresh(const metric::MetricMap& map, const Bounds* changed);
  // The cached voxels by column; the same as voxel_columns(map) after a
  // refresh that covered every change.
  VoxelColumns columns(double resolution) const;
  // The same into `out`, reusing its arrays (grown with headroom): the
  // arrays grow with the map, and new ones at every update would leave the
  // allocator holes a little too small for the next.
  void columns(double resolution, VoxelColumns& out) const;
  // Bytes held: every column of blocks' voxels and the block index, by capacity.
  std::size_t memory_bytes() const;

 private:
  using Block = metric::MetricMap::Blocks::Block;
  static constexpr int kLocalColumns = metric::kBlockEdge * metric::kBlockEdge;

  // One column of blocks: its 64 voxel columns as in VoxelColumns, local
  // column lx + 8 ly holding entries [start[c], start[c + 1]).
  struct BlockColumn {
    std::int32_t bx = 0, by = 0;
    std::vector<std::int32_t> block_z;  // the map's blocks here, ascending, as last read
    std::array<std::uint32_t, kLocalColumns + 1> start{};
    std::vector<std::int32_t> z;
    std::vector<ClassId> label;
    ColumnRect extent;  // of the occupied voxels
    // Scratch of refresh: the map's blocks here now, and whether one meets the change.
    std::vector<std::pair<std::int32_t, const Block*>> now;
    bool met = false;
  };
  void read(const metric::MetricMap& map, BlockColumn& column);
  // Makes the block index cover block columns [bx0, bx1] x [by0, by1].
  void cover(std::int32_t bx0, std::int32_t bx1, std::int32_t by0, std::int32_t by1);
  // slot_ of columns_ as they are now.
  void index_columns();

  std::vector<BlockColumn> columns_;  // every column of blocks that holds a block of the map
  // Dense over the block columns' extent: index into columns_, or -1.
  std::vector<std::int32_t> slot_;
  std::int32_t bx0_ = 0, by0_ = 0, bwidth_ = 0, bheight_ = 0;
};

}  // namespace sarmap::topo
