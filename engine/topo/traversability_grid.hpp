// The 2-D traversability grid projected from the metric map, as paper 001
// projects its semantic map onto a plane: in each column of voxels the
// walkable surface (the highest terrain or ramp voxel with the robot's height
// of space above it); one-cell gaps in seen ground filled in; columns
// of walls and obstacles, and the rims of drops (a platform's edge, a ramp's
// side), blocked; blocked cells grown by the robot's radius. The wavefront planner plans on it; grid.pgm shows it.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/classes.hpp"
#include "engine/topo/voxel_columns.hpp"
#include "engine/topo/planning_grid.hpp"
#include "engine/topo/topo_settings.hpp"

namespace sarmap::topo {

struct TraversabilityGrid {
  // Free: drivable; Occupied: wall, obstacle, drop rim or within the robot's
  // radius of one; Unknown: no voxel seen in the column. Cells are the map's
  // voxel columns.
  PlanningGrid grid;
  // Per cell (row-major as the grid), the walkable surface's height (the top
  // voxel's centre), before any blocking; NaN where there is none.
  std::vector<float> ground;
  // Per cell, the class of that surface (Unknown where there is none).
  std::vector<ClassId> ground_class;
  // Per cell, 1 within the robot's radius of a drop's rim: a drive through
  // such a cell would put a track over the edge.
  std::vector<std::uint8_t> near_drop;

  float ground_at(GridCell cell) const {
    return grid.contains(cell) ? ground[grid.index_of(cell)] : std::nanf("");
  }
  // Bytes held, by capacity.
  std::size_t memory_bytes() const {
    return grid.memory_bytes() + capacity_bytes(ground) + capacity_bytes(ground_class) + capacity_bytes(near_drop);
  }
};

// Cells are the columns' extent; no occupied voxel gives a 1 x 1 unknown grid
// at the origin.
TraversabilityGrid traversability_grid(const VoxelColumns& columns, const TopoSettings& settings);

// The arrays update_traversability_grid() reuses from one call to the next:
// the grid grows with the map, and arrays made new at every update leave the
// allocator holes a little too small for the next one.
struct TraversabilityScratch {
  TraversabilityGrid spare;  // the grid of a new extent is laid out here, then swapped in
  std::vector<CellState> seen, state;
  std::vector<float> ground;
  std::vector<ClassId> ground_class;

  std::size_t memory_bytes() const {
    return spare.memory_bytes() + capacity_bytes(seen) + capacity_bytes(state) + capacity_bytes(ground) +
           capacity_bytes(ground_class);
  }
};

// Brings a grid that traversability_grid() (or this) made with the same
// settings up to date with columns that differ from its own only within
// `changed`: the cells that can depend on those columns are computed again,
// the rest kept, so the grid equals traversability_grid(columns, settings).
// A grid of another extent is laid out on the columns' extent.
void update_traversability_grid(TraversabilityGrid& grid, const VoxelColumns& columns, const TopoSettings& settings,
                                const ColumnRect& changed, TraversabilityScratch& scratch);

}  // namespace sarmap::topo
