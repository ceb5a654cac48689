// A grid brought up to date where its columns changed equals one made from
// scratch: random worlds of ground at several heights (steps and drops),
// gaps, walls and overhangs, changed a rectangle at a time, inside the
// extent, across its edges (the extent grows) and cleared at an edge (it
// shrinks).
#include "engine/topo/traversability_grid.hpp"

#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace sarmap::topo {
namespace {

// Each column's voxels (z, label), bottom-up; a column without voxels is absent.
using ColumnWorld = std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::pair<std::int32_t, ClassId>>>;

VoxelColumns columns_of(const ColumnWorld& world) {
  VoxelColumns out;
  if (world.empty()) return out;
  std::int32_t x_lo = world.begin()->first.first, x_hi = x_lo, y_lo = world.begin()->first.second, y_hi = y_lo;
  for (const auto& [xy, voxels] : world) {
    x_lo = std::min(x_lo, xy.first);
    x_hi = std::max(x_hi, xy.first);
    y_lo = std::min(y_lo, xy.second);
    y_hi = std::max(y_hi, xy.second);
  }
  out.x0 = x_lo;
  out.y0 = y_lo;
  out.width = x_hi - x_lo + 1;
  out.height = y_hi - y_lo + 1;
  out.start.push_back(0);
  for (std::int32_t y = y_lo; y <= y_hi; ++y) {
    for (std::int32_t x = x_lo; x <= x_hi; ++x) {
      if (const auto it = world.find({x, y}); it != world.end()) {
        for (const auto& [z, label] : it->second) {
          out.z.push_back(z);
          out.label.push_back(label);
        }
      }
      out.start.push_back(static_cast<std::uint32_t>(out.z.size()));
    }
  }
  return out;
}

// Fills the rectangle with new columns: a patch of ground at one of a few
// heights (neighbouring patches a step or a drop apart), with gaps, walls
// and overhangs at random.
void paint(ColumnWorld& world, const ColumnRect& rect, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::int32_t base = std::array<std::int32_t, 4>{0, 1, 2, 9}[rng() % 4];
  const ClassId ground = std::array<ClassId, 3>{ClassId::Terrain, ClassId::InclinedRamp, ClassId::FlatRamp}[rng() % 3];
  for (std::int32_t y = rect.y0; y <= rect.y1; ++y) {
    for (std::int32_t x = rect.x0; x <= rect.x1; ++x) {
      const double r = u(rng);
      std::vector<std::pair<std::int32_t, ClassId>> voxels;
      if (r < 0.15) {
        world.erase({x, y});  // a gap, or unseen ground
        continue;
      }
      if (r < 0.22) {
        for (std::int32_t z = 0; z < 12; ++z) voxels.emplace_back(z, ClassId::Wall);
      } else {
        const std::int32_t top = base + static_cast<std::int32_t>(rng() % 2);
        voxels.emplace_back(top - 1, ClassId::Terrain);
        voxels.emplace_back(top, ground);
        if (u(rng) < 0.1) voxels.emplace_back(top + 1 + static_cast<std::int32_t>(rng() % 14), ClassId::Other);
      }
      world[{x, y}] = std::move(voxels);
    }
  }
}

void expect_same_grid(const TraversabilityGrid& a, const TraversabilityGrid& b, int step) {
  ASSERT_EQ(a.grid.width(), b.grid.width()) << step;
  ASSERT_EQ(a.grid.height(), b.grid.height()) << step;
  ASSERT_EQ(a.grid.origin(), b.grid.origin()) << step;
  ASSERT_TRUE(std::equal(a.grid.cells().begin(), a.grid.cells().end(), b.grid.cells().begin())) << step;
  ASSERT_EQ(a.ground.size(), b.ground.size()) << step;
  // Bit for bit, NaN included.
  ASSERT_EQ(std::memcmp(a.ground.data(), b.ground.data(), a.ground.size() * sizeof(float)), 0) << step;
  ASSERT_EQ(a.ground_class, b.ground_class) << step;
  ASSERT_EQ(a.near_drop, b.near_drop) << step;
}

TEST(TraversabilityGridUpdate, EqualsAGridMadeFromScratchAfterEveryChange) {
  TopoSettings settings;  // 0.2 m radius: blocked cells grow by 4 cells of 0.05 m
  for (unsigned seed = 1; seed <= 12; ++seed) {
    std::mt19937 rng(seed);
    ColumnWorld world;
    paint(world, {-20, 25, -10, 30}, rng);
    VoxelColumns columns = columns_of(world);
    columns.resolution = 0.05;
    TraversabilityGrid grid = traversability_grid(columns, settings);
    TraversabilityScratch scratch;
    std::size_t kept_cells = 0;
    for (int step = 0; step < 40; ++step) {
      const auto at = [&rng](std::int32_t lo, std::int32_t hi) {
        return lo + static_cast<std::int32_t>(rng() % static_cast<unsigned>(hi - lo + 1));
      };
      const std::int32_t left = columns.x0 + at(-12, columns.width + 4), bottom = columns.y0 + at(-12, columns.height + 4);
      const ColumnRect rect{left, left + at(0, 14), bottom, bottom + at(0, 14)};
      if (step % 7 == 6) {
        // Clear a strip at the low-x edge: the extent shrinks.
        const std::int32_t edge = columns.x0;
        std::erase_if(world, [edge](const auto& entry) { return entry.first.first <= edge + 2; });
        columns = columns_of(world);
        columns.resolution = 0.05;
        update_traversability_grid(grid, columns, settings, {edge, edge + 2, rect.y0 - 1000, rect.y1 + 1000}, scratch);
      } else {
        paint(world, rect, rng);
        columns = columns_of(world);
        columns.resolution = 0.05;
        update_traversability_grid(grid, columns, settings, rect, scratch);
      }
      const TraversabilityGrid whole = traversability_grid(columns, settings);
      expect_same_grid(grid, whole, step);
      kept_cells += whole.grid.cells().size();
    }
    EXPECT_GT(kept_cells, 0u);
  }
}

// The update reads only the changed columns and their surroundings: a change
// left out of `changed` stays out of the grid, while a cell beyond the
// robot's radius and the gap and rim margins of it is not.
TEST(TraversabilityGridUpdate, LeavesCellsFarFromTheChangeAsTheyWere) {
  TopoSettings settings;
  ColumnWorld world;  // flat terrain
  for (std::int32_t y = 0; y < 60; ++y) {
    for (std::int32_t x = 0; x < 60; ++x) world[{x, y}] = {{0, ClassId::Terrain}};
  }
  VoxelColumns columns = columns_of(world);
  columns.resolution = 0.05;
  TraversabilityGrid grid = traversability_grid(columns, settings);
  const TraversabilityGrid before = grid;
  TraversabilityScratch scratch;
  // A wall at (10, 10) and one at (50, 50), but only the first is named as changed.
  for (const auto& [x, y] : {std::pair{10, 10}, std::pair{50, 50}}) {
    std::vector<std::pair<std::int32_t, ClassId>> wall;
    for (std::int32_t z = 0; z < 12; ++z) wall.emplace_back(z, ClassId::Wall);
    world[{x, y}] = wall;
  }
  columns = columns_of(world);
  columns.resolution = 0.05;
  update_traversability_grid(grid, columns, settings, {10, 10, 10, 10}, scratch);
  EXPECT_EQ(grid.grid.at({10, 10}), CellState::Occupied);
  EXPECT_EQ(grid.grid.at({13, 10}), CellState::Occupied);  // within the robot's radius
  EXPECT_EQ(grid.grid.at({13, 13}), CellState::Free);        // beyond it
  EXPECT_EQ(grid.grid.at({50, 50}), CellState::Free);
  EXPECT_EQ(before.grid.at({50, 50}), CellState::Free);
  const TraversabilityGrid whole = traversability_grid(columns, settings);
  EXPECT_EQ(whole.grid.at({50, 50}), CellState::Occupied);
}

// The farthest a change reaches: a new column fills the gap beside it, the
// filled gap's ground lies a drop below a plateau cell one further on, and
// that rim blocks the robot's radius beyond it, reach + 2 cells from the
// change (0.02 m cells; heights in voxels: the new column 7, the gap's other
// side 10, the plateau 13, so only the filled gap's mean, 8.5, is a drop).
TEST(TraversabilityGridUpdate, AGapFilledByTheChangeMakesARimTwoCellsAway) {
  TopoSettings settings;  // radius 0.2 m: reach 10 cells
  ColumnWorld world;
  for (std::int32_t y = 0; y <= 40; ++y) {
    for (std::int32_t x = 29; x <= 60; ++x) world[{x, y}] = {{13, ClassId::Terrain}};
  }
  world[{29, 20}] = {{10, ClassId::Terrain}};
  world[{0, 0}] = {{13, ClassId::Terrain}};  // keeps the extent from x = 0
  VoxelColumns columns = columns_of(world);
  columns.resolution = 0.02;
  TraversabilityGrid grid = traversability_grid(columns, settings);
  TraversabilityScratch scratch;
  EXPECT_EQ(grid.grid.at({39, 21}), CellState::Free);
  world[{27, 20}] = {{7, ClassId::Terrain}};
  columns = columns_of(world);
  columns.resolution = 0.02;
  update_traversability_grid(grid, columns, settings, {27, 27, 20, 20}, scratch);
  const TraversabilityGrid whole = traversability_grid(columns, settings);
  EXPECT_EQ(whole.grid.at({39, 21}), CellState::Occupied);
  expect_same_grid(grid, whole, 0);
}

}  // namespace
}  // namespace sarmap::topo
