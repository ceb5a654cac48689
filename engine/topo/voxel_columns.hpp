// The metric map's occupied voxels gathered by column (x, y), bottom to top,
// with their classes: what the traversability grid and the wall scene both
// read, gathered once per update in linear time (a counting sort).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <span>
#include <vector>

#include "engine/core/bounds.hpp"
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
  std::size_t column(int x, int y) const { return static_cast<std::size_t>(x) + static_cast<std::size_t>(width) * y; }
};

// Deterministic whatever the hash order of the map's blocks.
VoxelColumns voxel_columns(const metric::MetricMap& map);

// The map's occupied voxels block by block, kept between updates so that an
// update rescans only the blocks a scan can have changed (a scan changes
// voxels only between its origin and its points), not the whole map.
class OccupiedVoxelCache {
 public:
  // Rescans the map's blocks that meet `changed` (every block when null) and
  // forgets blocks the map no longer holds.
  void refresh(const metric::MetricMap& map, const Bounds* changed);
  // The cached voxels by column; the same as voxel_columns(map) after a
  // refresh that covered every change.
  VoxelColumns columns(double resolution) const;

 private:
  struct Voxel {
    std::int32_t x, y, z;
    ClassId label;
  };
  std::unordered_map<std::uint64_t, std::vector<Voxel>> blocks_;
};

}  // namespace sarmap::topo
