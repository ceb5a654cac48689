// The wavefront planner against Dijkstra on the same 8-connected grid written
// the plainest way (scan for the nearest unsettled cell), on random grids
// with both unknown-cell policies; paths checked step by step; then blocked
// and outside ends, unreachable goals, unknown cells and corners by hand.
#include "engine/topo/wavefront_planner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace sarmap::topo {
namespace {

constexpr double kUnreachable = std::numeric_limits<double>::infinity();

bool passable(const PlanningGrid& grid, int x, int y, UnknownCells unknown) {
  if (!grid.contains({x, y})) return false;
  const CellState s = grid.at({x, y});
  return s == CellState::Free || (s == CellState::Unknown && unknown == UnknownCells::Free);
}

bool step_allowed(const PlanningGrid& grid, GridCell from, GridCell to, UnknownCells unknown) {
  const int dx = to.x - from.x;
  const int dy = to.y - from.y;
  if (std::abs(dx) > 1 || std::abs(dy) > 1 || (dx == 0 && dy == 0)) return false;
  if (!passable(grid, to.x, to.y, unknown)) return false;
  return dx == 0 || dy == 0 ||
         (passable(grid, from.x + dx, from.y, unknown) && passable(grid, from.x, from.y + dy, unknown));
}

// Distance in cells from `from` to every cell; O(cells^2).
std::vector<double> reference_distances(const PlanningGrid& grid, GridCell from, UnknownCells unknown) {
  const int w = grid.width();
  const std::size_t count = grid.cells().size();
  std::vector<double> distance(count, kUnreachable);
  std::vector<bool> settled(count, false);
  distance[grid.index_of(from)] = 0.0;
  while (true) {
    std::size_t best = count;
    for (std::size_t i = 0; i < count; ++i) {
      if (!settled[i] && distance[i] < kUnreachable && (best == count || distance[i] < distance[best])) best = i;
    }
    if (best == count) break;
    settled[best] = true;
    const GridCell c{static_cast<int>(best % w), static_cast<int>(best / w)};
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const GridCell n{c.x + dx, c.y + dy};
        if (!step_allowed(grid, c, n, unknown)) continue;
        const double step = dx != 0 && dy != 0 ? std::numbers::sqrt2 : 1.0;
        distance[grid.index_of(n)] = std::min(distance[grid.index_of(n)], distance[best] + step);
      }
    }
  }
  return distance;
}

void expect_valid_path(const PlanningGrid& grid, const GridPath& path, GridCell start, GridCell goal,
                       UnknownCells unknown) {
  ASSERT_TRUE(path.found());
  ASSERT_FALSE(path.cells.empty());
  EXPECT_EQ(path.cells.front(), start);
  EXPECT_EQ(path.cells.back(), goal);
  ASSERT_EQ(path.points.size(), path.cells.size());
  double length = 0.0;
  for (std::size_t i = 0; i < path.cells.size(); ++i) {
    EXPECT_TRUE(passable(grid, path.cells[i].x, path.cells[i].y, unknown));
    EXPECT_TRUE(path.points[i].isApprox(grid.centre_of(path.cells[i])));
    if (i == 0) continue;
    ASSERT_TRUE(step_allowed(grid, path.cells[i - 1], path.cells[i], unknown))
        << "step " << i << " from (" << path.cells[i - 1].x << ", " << path.cells[i - 1].y << ") to ("
        << path.cells[i].x << ", " << path.cells[i].y << ")";
    length += (path.points[i] - path.points[i - 1]).norm();
  }
  EXPECT_NEAR(path.length_m, length, 1e-9);
}

PlanningGrid random_grid(std::mt19937& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int width = 1 + static_cast<int>(random() % 28);
  const int height = 1 + static_cast<int>(random() % 28);
  PlanningGrid grid(width, height, 0.05 + 0.2 * unit(random),
                    Eigen::Vector2d(unit(random) - 0.5, unit(random)), CellState::Free);
  const double occupied = 0.45 * unit(random);
  const double unknown = 0.25 * unit(random);
  for (CellState& c : grid.cells()) {
    const double r = unit(random);
    c = r < occupied ? CellState::Occupied : r < occupied + unknown ? CellState::Unknown : CellState::Free;
  }
  return grid;
}

TEST(WavefrontPlanner, MatchesPlainDijkstraOnRandomGrids) {
  std::mt19937 random(1);
  int found = 0;
  int unreachable = 0;
  int blocked = 0;
  for (int round = 0; round < 150; ++round) {
    SCOPED_TRACE("grid " + std::to_string(round));
    PlanningGrid grid = random_grid(random);
    const UnknownCells unknown = round % 2 ? UnknownCells::Free : UnknownCells::Blocked;
    WavefrontPlanner planner({unknown});
    for (int q = 0; q < 4; ++q) {
      const GridCell start{static_cast<int>(random() % grid.width()),
                           static_cast<int>(random() % grid.height())};
      const GridCell goal{static_cast<int>(random() % grid.width()),
                          static_cast<int>(random() % grid.height())};
      // Mostly free ends, so most queries reach the wave.
      if (q < 3) {
        grid.set(start, CellState::Free);
        grid.set(goal, CellState::Free);
      }
      const GridPath path = planner.plan(grid, start, goal);
      if (!passable(grid, start.x, start.y, unknown)) {
        EXPECT_EQ(path.status, GridPlanStatus::StartBlocked);
        ++blocked;
        continue;
      }
      if (!passable(grid, goal.x, goal.y, unknown)) {
        EXPECT_EQ(path.status, GridPlanStatus::GoalBlocked);
        ++blocked;
        continue;
      }
      const double reference = reference_distances(grid, start, unknown)[grid.index_of(goal)];
      if (reference == kUnreachable) {
        EXPECT_EQ(path.status, GridPlanStatus::Unreachable);
        EXPECT_TRUE(path.cells.empty());
        ++unreachable;
        continue;
      }
      ++found;
      EXPECT_NEAR(path.length_m, reference * grid.resolution(), 1e-9);
      expect_valid_path(grid, path, start, goal, unknown);
    }
  }
  EXPECT_GT(found, 250);
  EXPECT_GT(unreachable, 30);
  EXPECT_GT(blocked, 20);
}

TEST(WavefrontPlanner, EmptyGridGivesTheOctileDistance) {
  const PlanningGrid grid(200, 120, 0.1, Eigen::Vector2d::Zero(), CellState::Free);
  const GridPath path = plan_wavefront(grid, {3, 5}, {190, 100});
  // 187 across, 95 up: 95 diagonal steps and 92 straight ones.
  EXPECT_TRUE(path.found());
  EXPECT_NEAR(path.length_m, (92 + 95 * std::numbers::sqrt2) * 0.1, 1e-9);
  EXPECT_EQ(path.cells.size(), 188u);
}

TEST(WavefrontPlanner, StartEqualToGoalIsAPathOfOneCell) {
  const PlanningGrid grid(3, 3, 0.5, Eigen::Vector2d::Zero(), CellState::Free);
  const GridPath path = plan_wavefront(grid, {1, 2}, {1, 2});
  EXPECT_TRUE(path.found());
  EXPECT_EQ(path.cells, (std::vector<GridCell>{{1, 2}}));
  EXPECT_EQ(path.length_m, 0.0);
}

TEST(WavefrontPlanner, BlockedAndOutsideEndsAreNamed) {
  PlanningGrid grid(4, 4, 0.5, Eigen::Vector2d::Zero(), CellState::Free);
  grid.set({0, 0}, CellState::Occupied);
  grid.set({3, 3}, CellState::Occupied);
  EXPECT_EQ(plan_wavefront(grid, {0, 0}, {2, 2}).status, GridPlanStatus::StartBlocked);
  EXPECT_EQ(plan_wavefront(grid, {1, 1}, {3, 3}).status, GridPlanStatus::GoalBlocked);
  // Both blocked: the start is reported.
  EXPECT_EQ(plan_wavefront(grid, {0, 0}, {3, 3}).status, GridPlanStatus::StartBlocked);
  EXPECT_EQ(plan_wavefront(grid, {-1, 0}, {2, 2}).status, GridPlanStatus::StartOutside);
  EXPECT_EQ(plan_wavefront(grid, {1, 1}, {1, 4}).status, GridPlanStatus::GoalOutside);
  EXPECT_EQ(to_string(GridPlanStatus::StartBlocked), "start_blocked");
  EXPECT_EQ(to_string(GridPlanStatus::GoalBlocked), "goal_blocked");
  EXPECT_EQ(to_string(GridPlanStatus::Unreachable), "unreachable");
  EXPECT_EQ(to_string(GridPlanStatus::Found), "found");
  const GridPath failed = plan_wavefront(grid, {0, 0}, {2, 2});
  EXPECT_FALSE(failed.found());
  EXPECT_TRUE(failed.cells.empty() && failed.points.empty());
  EXPECT_EQ(failed.length_m, 0.0);
}

TEST(WavefrontPlanner, AWallMakesTheGoalUnreachable) {
  PlanningGrid grid(7, 5, 0.1, Eigen::Vector2d::Zero(), CellState::Free);
  for (int y = 0; y < 5; ++y) grid.set({3, y}, CellState::Occupied);
  const GridPath path = plan_wavefront(grid, {0, 2}, {6, 2});
  EXPECT_EQ(path.status, GridPlanStatus::Unreachable);
  EXPECT_EQ(to_string(path.status), "unreachable");
  // The wave filled the goal's side (3 x 5 cells) and stopped.
  EXPECT_EQ(path.settled_cells, 15u);
}

TEST(WavefrontPlanner, UnknownCellsFollowTheSetting) {
  // The wall has one unknown gap at (3, 2).
  PlanningGrid grid(7, 5, 0.1, Eigen::Vector2d::Zero(), CellState::Free);
  for (int y = 0; y < 5; ++y) grid.set({3, y}, CellState::Occupied);
  grid.set({3, 2}, CellState::Unknown);
  EXPECT_EQ(plan_wavefront(grid, {0, 2}, {6, 2}, {UnknownCells::Blocked}).status,
            GridPlanStatus::Unreachable);
  const GridPath through = plan_wavefront(grid, {0, 2}, {6, 2}, {UnknownCells::Free});
  ASSERT_TRUE(through.found());
  EXPECT_NEAR(through.length_m, 0.6, 1e-12);
  EXPECT_NE(std::find(through.cells.begin(), through.cells.end(), GridCell{3, 2}), through.cells.end());
  // An unknown start is blocked only when unknown cells are.
  grid.set({0, 2}, CellState::Unknown);
  EXPECT_EQ(plan_wavefront(grid, {0, 2}, {6, 2}, {UnknownCells::Blocked}).status,
            GridPlanStatus::StartBlocked);
  EXPECT_TRUE(plan_wavefront(grid, {0, 2}, {6, 2}, {UnknownCells::Free}).found());
}

TEST(WavefrontPlanner, DiagonalsNeverCutABlockedCorner) {
  // Two blocked cells touching at a corner: no squeezing between them.
  //   . #
  //   # .
  PlanningGrid pinch(2, 2, 1.0, Eigen::Vector2d::Zero(), CellState::Free);
  pinch.set({1, 0}, CellState::Occupied);
  pinch.set({0, 1}, CellState::Occupied);
  EXPECT_EQ(plan_wavefront(pinch, {0, 0}, {1, 1}).status, GridPlanStatus::Unreachable);
  // One blocked cell: the diagonal past its corner is refused, so the path
  // goes round in two straight steps.
  PlanningGrid corner(2, 2, 1.0, Eigen::Vector2d::Zero(), CellState::Free);
  corner.set({1, 0}, CellState::Occupied);
  const GridPath path = plan_wavefront(corner, {0, 0}, {1, 1});
  ASSERT_TRUE(path.found());
  EXPECT_EQ(path.cells, (std::vector<GridCell>{{0, 0}, {0, 1}, {1, 1}}));
  EXPECT_EQ(path.length_m, 2.0);
  // The same with an unknown cell, when unknown cells are blocked.
  corner.set({1, 0}, CellState::Unknown);
  EXPECT_EQ(plan_wavefront(corner, {0, 0}, {1, 1}, {UnknownCells::Blocked}).length_m, 2.0);
  EXPECT_NEAR(plan_wavefront(corner, {0, 0}, {1, 1}, {UnknownCells::Free}).length_m, std::numbers::sqrt2,
              1e-12);
}

TEST(WavefrontPlanner, WorldPointsPlanBetweenTheirCells) {
  const PlanningGrid grid(20, 10, 0.25, Eigen::Vector2d(-2.0, 1.0), CellState::Free);
  WavefrontPlanner planner;
  const GridPath path = planner.plan(grid, Eigen::Vector2d(-1.9, 1.1), Eigen::Vector2d(2.9, 1.2));
  ASSERT_TRUE(path.found());
  EXPECT_EQ(path.cells.front(), (GridCell{0, 0}));
  EXPECT_EQ(path.cells.back(), (GridCell{19, 0}));
  EXPECT_NEAR(path.length_m, 19 * 0.25, 1e-12);
  EXPECT_TRUE(path.points.front().isApprox(Eigen::Vector2d(-1.875, 1.125)));
  EXPECT_EQ(planner.plan(grid, Eigen::Vector2d(-2.1, 1.1), Eigen::Vector2d(0, 2)).status,
            GridPlanStatus::StartOutside);
  EXPECT_EQ(planner.plan(grid, Eigen::Vector2d(0, 2), Eigen::Vector2d(0, 3.6)).status,
            GridPlanStatus::GoalOutside);
}

TEST(WavefrontPlanner, OnePlannerServesGridsOfDifferentSizes) {
  WavefrontPlanner planner;
  const PlanningGrid large(50, 40, 0.1, Eigen::Vector2d::Zero(), CellState::Free);
  const PlanningGrid small(3, 2, 0.1, Eigen::Vector2d::Zero(), CellState::Free);
  EXPECT_NEAR(planner.plan(large, GridCell{0, 0}, GridCell{49, 0}).length_m, 4.9, 1e-12);
  EXPECT_NEAR(planner.plan(small, GridCell{0, 0}, GridCell{2, 0}).length_m, 0.2, 1e-12);
  EXPECT_NEAR(planner.plan(large, GridCell{0, 0}, GridCell{0, 39}).length_m, 3.9, 1e-12);
}

}  // namespace
}  // namespace sarmap::topo
