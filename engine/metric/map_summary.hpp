// What a metric map holds, counted in one pass over its blocks: the figures
// `sarmap info map.sarmap` reports (voxels by state, occupied voxels by
// class, the extent of what is known and of what is occupied).
#pragma once

#include <array>
#include <cstddef>

#include "engine/core/bounds.hpp"
#include "engine/core/classes.hpp"
#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

struct MapSummary {
  MapCounts counts;  // the same figures as MetricMap::counts()
  // Occupied voxels by dominant class (index = class id; Unknown: occupied
  // voxels no labelled point fell in).
  std::array<std::size_t, kClassCount> occupied_by_class{};
  // Outer faces of the voxels (not their centres), metres; empty when none.
  Bounds known_bounds;
  Bounds occupied_bounds;
};

// Costs one pass over every voxel of every block.
MapSummary summarize_map(const MetricMap& map);

}  // namespace sarmap::metric
