// What a metric map holds, counted from its blocks: the figures
// `sarmap info map.sarmap` reports (voxels by state, occupied voxels by
// class, the extent of what is known and of what is occupied, and how many
// blocks are uniform: what a coarser level of whole uniform blocks, as
// OctoMap prunes its tree, could store as fewer records).
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
  // Blocks whose 512 voxels share one log-odds and hold no class evidence
  // (stored as a record without a slab: semantic_block.hpp).
  std::size_t uniform_blocks = 0;
  // Uniform blocks that fill a whole aligned 2 x 2 x 2 group of blocks with
  // one value: the records a coarser level could replace by one per group.
  std::size_t blocks_in_uniform_groups = 0;
};

// Costs one pass over every voxel of every block and one over the blocks.
MapSummary summarize_map(const MetricMap& map);

}  // namespace sarmap::metric
