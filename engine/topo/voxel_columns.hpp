// The metric map's occupied voxels gathered by column (x, y), bottom to top,
// with their classes: what the traversability grid and the wall scene both
// read, gathered once per update in linear time (a counting sort).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

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

}  // namespace sarmap::topo
