#include "engine/eval/truth_paths.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <queue>
#include <utility>
#include <variant>

#include "engine/core/degrees.hpp"
#include "engine/core/error.hpp"
#include "engine/geometry/segment_box.hpp"

namespace sarmap::eval {
namespace {

double polyline_length(const std::vector<Eigen::Vector3d>& points) {
  double length = 0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

GridCell cell_at(const DrivableGrid& grid, std::size_t k) {
  const auto w = static_cast<std::size_t>(grid.width());
  return {static_cast<std::int32_t>(k % w), static_cast<std::int32_t>(k / w)};
}

// Theta* (Nash et al. 2007): A* on the same cells whose parent may be any
// earlier cell in straight, passable sight, so its lines run at any angle.
// Returns the cells of its path, goal first; empty when there is none.
std::vector<std::size_t> any_angle_cells(const DrivableGrid& grid, const GridCell& start, const GridCell& goal) {
  const std::size_t n = static_cast<std::size_t>(grid.width()) * static_cast<std::size_t>(grid.height());
  std::vector<double> cost(n, std::numeric_limits<double>::infinity());
  std::vector<std::size_t> parent(n);
  std::vector<std::uint8_t> closed(n, 0);
  const Eigen::Vector3d target = grid.center(goal);
  // Straight-line distance in the plane: never more than the 3-D path left.
  const auto estimate = [&](const Eigen::Vector3d& p) { return (target - p).head<2>().norm(); };
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  const std::size_t s = grid.index(start), g = grid.index(goal);
  cost[s] = 0;
  parent[s] = s;
  open.push({estimate(grid.center(start)), s});
  while (!open.empty()) {
    const std::size_t k = open.top().second;
    open.pop();
    if (closed[k]) continue;
    closed[k] = 1;
    if (k == g) break;
    const GridCell a = cell_at(grid, k);
    const Eigen::Vector3d pa = grid.center(a);
    const std::size_t up = parent[k];
    const Eigen::Vector3d pp = grid.center(cell_at(grid, up));
    for (std::int32_t dy = -1; dy <= 1; ++dy) {
      for (std::int32_t dx = -1; dx <= 1; ++dx) {
        const GridCell b{a.x + dx, a.y + dy};
        if ((dx == 0 && dy == 0) || !grid.passable(a, b) || closed[grid.index(b)]) continue;
        const Eigen::Vector3d pb = grid.center(b);
        double through = cost[k] + (pb - pa).norm();
        std::size_t via = k;
        if (up != k && line_passable(grid, pp, pb)) {
          through = cost[up] + (pb - pp).norm();
          via = up;
        }
        const std::size_t kb = grid.index(b);
        if (through < cost[kb]) {
          cost[kb] = through;
          parent[kb] = via;
          open.push({through + estimate(pb), kb});
        }
      }
    }
  }
  if (!closed[g]) return {};
  std::vector<std::size_t> cells{g};
  while (cells.back() != s) cells.push_back(parent[cells.back()]);
  return cells;
}

// The start and goal at their surface heights with the cell centres between.
std::vector<Eigen::Vector3d> path_points(const DrivableGrid& grid, const std::vector<std::size_t>& cells,
                                         const Eigen::Vector3d& start, const Eigen::Vector3d& goal) {
  const GridCell first = cell_at(grid, cells.back()), last = cell_at(grid, cells.front());
  std::vector<Eigen::Vector3d> points{{start.x(), start.y(), grid.surface(first)}};
  for (std::size_t i = cells.size() - 1; i-- > 1;) points.push_back(grid.center(cell_at(grid, cells[i])));
  points.emplace_back(goal.x(), goal.y(), grid.surface(last));
  return points;
}

}  // namespace

bool line_passable(const DrivableGrid& grid, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  std::optional<GridCell> prev = grid.cell_of(a.x(), a.y());
  if (!prev || grid.blocked(*prev)) return false;
  // A quarter cell apart, consecutive samples lie in the same or neighbouring cells.
  const double span = (b - a).head<2>().norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(4 * span / grid.settings().cell)));
  for (int k = 1; k <= steps; ++k) {
    const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(k) / steps);
    const std::optional<GridCell> c = grid.cell_of(p.x(), p.y());
    if (!c) return false;
    if (*c == *prev) continue;
    if (!grid.passable(*prev, *c)) return false;
    prev = c;
  }
  return true;
}

std::string_view path_status_name(PathStatus status) {
  switch (status) {
    case PathStatus::Found: return "found";
    case PathStatus::OutsideArena: return "outside_arena";
    case PathStatus::OffSurface: return "off_surface";
    case PathStatus::StartBlocked: return "start_blocked";
    case PathStatus::GoalBlocked: return "goal_blocked";
    case PathStatus::Unreachable: return "unreachable";
  }
  return "unreachable";
}

TruthPath shortest_path(const DrivableGrid& grid, const Eigen::Vector3d& start, const Eigen::Vector3d& goal) {
  TruthPath out;
  const std::optional<GridCell> s = grid.cell_of(start.x(), start.y());
  const std::optional<GridCell> g = grid.cell_of(goal.x(), goal.y());
  if (!s || !g) {
    out.status = PathStatus::OutsideArena;
    return out;
  }
  if (grid.blocked(*s)) {
    out.status = PathStatus::StartBlocked;
    return out;
  }
  if (grid.blocked(*g)) {
    out.status = PathStatus::GoalBlocked;
    return out;
  }
  const double tolerance = grid.settings().surface_tolerance;
  if (std::abs(start.z() - grid.surface(*s)) > tolerance || std::abs(goal.z() - grid.surface(*g)) > tolerance) {
    out.status = PathStatus::OffSurface;
    return out;
  }

  const std::size_t n = static_cast<std::size_t>(grid.width()) * static_cast<std::size_t>(grid.height());
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<std::int64_t> prev(n, -1);
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  dist[grid.index(*s)] = 0;
  open.push({0.0, grid.index(*s)});
  const std::size_t target = grid.index(*g);
  const double cell = grid.settings().cell;
  while (!open.empty()) {
    const auto [d, k] = open.top();
    open.pop();
    if (d > dist[k]) continue;
    if (k == target) break;
    const GridCell a = cell_at(grid, k);
    for (std::int32_t dy = -1; dy <= 1; ++dy) {
      for (std::int32_t dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        const GridCell b{a.x + dx, a.y + dy};
        if (!grid.passable(a, b)) continue;
        const double dz = grid.surface(b) - grid.surface(a);
        const double step = std::sqrt(cell * cell * (dx * dx + dy * dy) + dz * dz);
        const std::size_t kb = grid.index(b);
        if (d + step < dist[kb]) {
          dist[kb] = d + step;
          prev[kb] = static_cast<std::int64_t>(k);
          open.push({dist[kb], kb});
        }
      }
    }
  }
  if (!std::isfinite(dist[target])) {
    out.status = PathStatus::Unreachable;
    return out;
  }

  std::vector<std::size_t> cells;
  for (std::int64_t k = static_cast<std::int64_t>(target); k >= 0; k = prev[static_cast<std::size_t>(k)]) {
    cells.push_back(static_cast<std::size_t>(k));
  }
  out.points = path_points(grid, cells, start, goal);
  out.length = polyline_length(out.points);
  out.any_angle_points = path_points(grid, any_angle_cells(grid, *s, *g), start, goal);
  out.any_angle_length = polyline_length(out.any_angle_points);
  out.found = true;
  out.status = PathStatus::Found;
  return out;
}

TruthPath truth_path(const sim::Arena& arena, const Eigen::Vector3d& start, const Eigen::Vector3d& goal,
                     const DrivableSettings& settings) {
  return shortest_path(DrivableGrid(arena, settings), start, goal);
}

std::vector<geometry::OrientedBox> wall_and_box_solids(const sim::Arena& arena) {
  std::vector<geometry::OrientedBox> boxes;
  for (const sim::ArenaElement& e : arena.elements) {
    if (const auto* w = std::get_if<sim::WallSpec>(&e.shape)) {
      // As sim::element_mesh builds it: the segment lengthened by the
      // thickness, so walls meeting at a corner close it.
      const Eigen::Vector2d d = w->to - w->from;
      const Eigen::Vector2d mid = (w->from + w->to) / 2;
      boxes.push_back(geometry::yawed_box({mid.x(), mid.y(), w->height / 2},
                                          {d.norm() + w->thickness, w->thickness, w->height}, std::atan2(d.y(), d.x())));
    } else if (const auto* b = std::get_if<sim::BoxSpec>(&e.shape)) {
      boxes.push_back(geometry::yawed_box(b->center, b->size, b->yaw_deg * kDeg));
    }
  }
  return boxes;
}

std::vector<bool> segments_crossing_walls(const sim::Arena& arena, std::span<const geometry::Segment> segments) {
  for (const geometry::Segment& s : segments) {
    if (!s.p.allFinite() || !s.q.allFinite()) {
      throw Error(ErrorCode::InvalidArgument, "segments_crossing_walls: a segment's endpoint is not finite");
    }
  }
  const std::vector<geometry::OrientedBox> boxes = wall_and_box_solids(arena);
  std::vector<bool> out(segments.size(), false);
  for (std::size_t i = 0; i < segments.size(); ++i) {
    for (const geometry::OrientedBox& box : boxes) {
      if (geometry::segment_intersects_box(segments[i], box)) {
        out[i] = true;
        break;
      }
    }
  }
  return out;
}

}  // namespace sarmap::eval
