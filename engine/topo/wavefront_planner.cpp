#include "engine/topo/wavefront_planner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace sarmap::topo {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct Step {
  int dx;
  int dy;
  double length;  // in cells
};

// Straight steps first: on a tie the descent takes the first, and this order
// is what makes the path a fixed function of the grid.
constexpr std::array<Step, 8> kSteps{{{1, 0, 1.0},
                                      {0, 1, 1.0},
                                      {-1, 0, 1.0},
                                      {0, -1, 1.0},
                                      {1, 1, std::numbers::sqrt2},
                                      {-1, 1, std::numbers::sqrt2},
                                      {-1, -1, std::numbers::sqrt2},
                                      {1, -1, std::numbers::sqrt2}}};

struct ComesOutLater {
  template <typename Entry>
  bool operator()(const Entry& x, const Entry& y) const {
    if (x.distance != y.distance) return x.distance > y.distance;
    return x.cell > y.cell;
  }
};

}  // namespace

std::string_view to_string(GridPlanStatus status) {
  switch (status) {
    case GridPlanStatus::Found:
      return "found";
    case GridPlanStatus::StartOutside:
      return "start_outside";
    case GridPlanStatus::GoalOutside:
      return "goal_outside";
    case GridPlanStatus::StartBlocked:
      return "start_blocked";
    case GridPlanStatus::GoalBlocked:
      return "goal_blocked";
    case GridPlanStatus::Unreachable:
      return "unreachable";
  }
  return "unknown";
}

void WavefrontPlanner::load(const PlanningGrid& grid) {
  padded_width_ = grid.width() + 2;
  const std::size_t padded_cells =
      static_cast<std::size_t>(padded_width_) * static_cast<std::size_t>(grid.height() + 2);
  passable_.assign(padded_cells, 0);
  distance_.assign(padded_cells, kInfinity);
  const bool unknown_is_free = settings_.unknown_cells == UnknownCells::Free;
  const std::span<const CellState> cells = grid.cells();
  for (int y = 0; y < grid.height(); ++y) {
    const CellState* row =
        cells.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(grid.width());
    std::uint8_t* padded_row = passable_.data() + static_cast<std::size_t>(y + 1) * padded_width_ + 1;
    for (int x = 0; x < grid.width(); ++x) {
      padded_row[x] = row[x] == CellState::Free || (unknown_is_free && row[x] == CellState::Unknown);
    }
  }
}

// Dijkstra's wave from the goal, stopped when the start is settled: every
// cell nearer the goal than the start is final by then, and those are all the
// descent can step on.
bool WavefrontPlanner::propagate(std::size_t goal, std::size_t start, std::size_t& settled) {
  std::array<std::int64_t, 8> offsets{};
  for (std::size_t s = 0; s < kSteps.size(); ++s)
    offsets[s] = kSteps[s].dx + std::int64_t{kSteps[s].dy} * padded_width_;
  heap_.clear();
  distance_[goal] = 0.0;
  heap_.push_back({0.0, goal});
  settled = 0;
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), ComesOutLater{});
    const WaveEntry top = heap_.back();
    heap_.pop_back();
    if (top.distance > distance_[top.cell]) continue;  // outdated entry
    ++settled;
    if (top.cell == start) return true;
    for (std::size_t s = 0; s < kSteps.size(); ++s) {
      const auto next = static_cast<std::size_t>(top.cell + offsets[s]);
      if (!passable_[next]) continue;
      if (s >= 4 &&
          !(passable_[top.cell + offsets[s] - kSteps[s].dx] && passable_[top.cell + kSteps[s].dx])) {
        continue;  // a diagonal past a blocked cell
      }
      const double distance = top.distance + kSteps[s].length;
      if (distance >= distance_[next]) continue;
      distance_[next] = distance;
      heap_.push_back({distance, next});
      std::push_heap(heap_.begin(), heap_.end(), ComesOutLater{});
    }
  }
  return false;
}

// Downhill along the wave: each step goes to the neighbour with the least
// distance-plus-step, not merely the least distance, because where obstacles
// bend the wave the lowest neighbour can sit off every shortest path.
void WavefrontPlanner::descend(std::size_t start, std::size_t goal, const PlanningGrid& grid,
                               GridPath& path) const {
  std::size_t straight_steps = 0;
  std::size_t diagonal_steps = 0;
  const auto cell_of = [&](std::size_t padded) {
    return GridCell{static_cast<int>(padded % padded_width_) - 1,
                    static_cast<int>(padded / padded_width_) - 1};
  };
  std::size_t current = start;
  path.cells.push_back(cell_of(current));
  while (current != goal) {
    std::size_t best = current;
    double best_value = kInfinity;
    std::size_t best_step = 0;
    for (std::size_t s = 0; s < kSteps.size(); ++s) {
      const std::int64_t offset = kSteps[s].dx + std::int64_t{kSteps[s].dy} * padded_width_;
      const auto next = static_cast<std::size_t>(current + offset);
      if (!passable_[next]) continue;
      if (s >= 4 && !(passable_[current + offset - kSteps[s].dx] && passable_[current + kSteps[s].dx]))
        continue;
      const double value = distance_[next] + kSteps[s].length;
      if (value < best_value) {
        best_value = value;
        best = next;
        best_step = s;
      }
    }
    // The wave set distance_[current] to some neighbour's distance plus its
    // step, so the best is at most that and strictly below current's own.
    if (best == current || !(distance_[best] < distance_[current])) {
      throw std::logic_error("wavefront: the descent found no lower neighbour");
    }
    (best_step < 4 ? straight_steps : diagonal_steps) += 1;
    current = best;
    path.cells.push_back(cell_of(current));
  }
  path.length_m =
      (static_cast<double>(straight_steps) + static_cast<double>(diagonal_steps) * std::numbers::sqrt2) *
      grid.resolution();
  path.points.reserve(path.cells.size());
  for (const GridCell& c : path.cells) path.points.push_back(grid.centre_of(c));
}

GridPath WavefrontPlanner::plan(const PlanningGrid& grid, GridCell start, GridCell goal) {
  GridPath path;
  if (!grid.contains(start)) {
    path.status = GridPlanStatus::StartOutside;
    return path;
  }
  if (!grid.contains(goal)) {
    path.status = GridPlanStatus::GoalOutside;
    return path;
  }
  load(grid);
  const auto padded = [&](GridCell c) {
    return static_cast<std::size_t>(c.y + 1) * static_cast<std::size_t>(padded_width_) +
           static_cast<std::size_t>(c.x + 1);
  };
  const std::size_t start_cell = padded(start);
  const std::size_t goal_cell = padded(goal);
  if (!passable_[start_cell]) {
    path.status = GridPlanStatus::StartBlocked;
    return path;
  }
  if (!passable_[goal_cell]) {
    path.status = GridPlanStatus::GoalBlocked;
    return path;
  }
  if (!propagate(goal_cell, start_cell, path.settled_cells)) {
    path.status = GridPlanStatus::Unreachable;
    return path;
  }
  path.status = GridPlanStatus::Found;
  descend(start_cell, goal_cell, grid, path);
  return path;
}

GridPath WavefrontPlanner::plan(const PlanningGrid& grid, const Eigen::Vector2d& start,
                                const Eigen::Vector2d& goal) {
  return plan(grid, grid.cell_at(start), grid.cell_at(goal));
}

GridPath plan_wavefront(const PlanningGrid& grid, GridCell start, GridCell goal, WavefrontSettings settings) {
  return WavefrontPlanner(settings).plan(grid, start, goal);
}

}  // namespace sarmap::topo
