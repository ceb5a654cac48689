// Wave-propagation path planning on a PlanningGrid, as paper 001 plans on its
// traversability grid: a wave spreads from the goal over free cells until it
// reaches the start, then the path runs downhill from the start to the goal.
// An independent second planner beside the topological map's graph searches.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "engine/topo/planning_grid.hpp"

namespace sarmap::topo {

// Paper 001 treats what it cannot classify as not traversable, hence the default.
enum class UnknownCells : std::uint8_t { Blocked, Free };

struct WavefrontSettings {
  UnknownCells unknown_cells = UnknownCells::Blocked;
};

enum class GridPlanStatus : std::uint8_t {
  Found,
  StartOutside,
  GoalOutside,
  StartBlocked,
  GoalBlocked,
  Unreachable
};
// "found", "start_outside", "goal_outside", "start_blocked", "goal_blocked", "unreachable".
std::string_view to_string(GridPlanStatus status);

struct GridPath {
  GridPlanStatus status = GridPlanStatus::Unreachable;
  bool found() const { return status == GridPlanStatus::Found; }
  std::vector<GridCell> cells;          // start first, goal last; 8-connected steps
  std::vector<Eigen::Vector2d> points;  // the cells' centres in world coordinates
  double length_m = 0.0;                // between cell centres; 0 when not found
  std::size_t settled_cells = 0;        // cells the wave fixed before it reached the start
};

// Moves are to the 8 neighbours at 1 and sqrt(2) cells; a diagonal move needs
// both cells beside it passable too, so a path never slips between two
// blocked cells that touch at a corner nor grazes a blocked corner. Keeps its
// buffers between plans; not thread-safe (one per thread).
class WavefrontPlanner {
 public:
  explicit WavefrontPlanner(WavefrontSettings settings = {}) : settings_(settings) {}

  GridPath plan(const PlanningGrid& grid, GridCell start, GridCell goal);
  // From and to the cells holding these world points.
  GridPath plan(const PlanningGrid& grid, const Eigen::Vector2d& start, const Eigen::Vector2d& goal);

  const WavefrontSettings& settings() const { return settings_; }

 private:
  struct WaveEntry {
    double distance;
    std::size_t cell;  // index in the padded grid
  };

  void load(const PlanningGrid& grid);
  bool propagate(std::size_t goal, std::size_t start, std::size_t& settled);
  void descend(std::size_t start, std::size_t goal, const PlanningGrid& grid, GridPath& path) const;

  WavefrontSettings settings_;
  // The grid with a one-cell blocked border, so neighbour steps need no bounds tests.
  int padded_width_ = 0;
  std::vector<std::uint8_t> passable_;
  std::vector<double> distance_;  // to the goal in cells; infinity where the wave has not been
  std::vector<WaveEntry> heap_;
};

GridPath plan_wavefront(const PlanningGrid& grid, GridCell start, GridCell goal,
                        WavefrontSettings settings = {});

}  // namespace sarmap::topo
