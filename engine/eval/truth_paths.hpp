// Ground truth for the path figures: the shortest drivable path between two
// points of an arena (8-connected Dijkstra with 3-D step lengths on the
// drivable grid, and its any-angle counterpart), and whether straight 3-D segments (a graph's edges) cross
// any true wall or box, by an exact test independent of Embree.
#pragma once

#include <span>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "engine/eval/drivable_grid.hpp"
#include "engine/geometry/oriented_box.hpp"
#include "engine/geometry/segment.hpp"
#include "engine/sim/arena.hpp"

namespace sarmap::eval {

enum class PathStatus {
  Found,
  OutsideArena,  // the start or goal lies outside the arena's bounds
  OffSurface,    // the start or goal lies farther than surface_tolerance from the surface under it
  StartBlocked,  // within the robot's radius of an obstacle, or over no surface
  GoalBlocked,
  Unreachable,   // no chain of passable cells joins them
};

// "found", "outside_arena", "off_surface", "start_blocked", "goal_blocked", "unreachable".
std::string_view path_status_name(PathStatus status);

struct TruthPath {
  bool found = false;
  PathStatus status = PathStatus::Unreachable;
  double length = 0;  // metres, along `points`
  // The start and goal at their surface heights, and between them the centres
  // of the cells passed, at theirs; empty unless found.
  std::vector<Eigen::Vector3d> points;
  // The any-angle shortest path (Theta*) on the same cells: an 8-connected
  // path runs up to 8% longer than the straight lines a robot would drive,
  // this one only by how its corners sit on cell centres. Its straight lines
  // cross only passable cells (line_passable); the ends are as in `points`.
  double any_angle_length = 0;  // metres
  std::vector<Eigen::Vector3d> any_angle_points;
};

// The shortest path on `grid` from start to goal (each taken to the cell
// holding its x and y).
TruthPath shortest_path(const DrivableGrid& grid, const Eigen::Vector3d& start, const Eigen::Vector3d& goal);
// Whether the straight line from a to b (in x and y) passes only through
// cells each passable from the one before it.
bool line_passable(const DrivableGrid& grid, const Eigen::Vector3d& a, const Eigen::Vector3d& b);
// The same on a grid built for the one query.
TruthPath truth_path(const sim::Arena& arena, const Eigen::Vector3d& start, const Eigen::Vector3d& goal,
                     const DrivableSettings& settings = {});

// The solid boxes of the arena's walls and box obstacles, as the simulator
// builds their meshes.
std::vector<geometry::OrientedBox> wall_and_box_solids(const sim::Arena& arena);

// Per segment, whether it shares a point with any wall or box of the arena
// (touching counts): geometry::segment_intersects_box, in double precision.
// Throws sarmap::Error (InvalidArgument) for a non-finite endpoint.
std::vector<bool> segments_crossing_walls(const sim::Arena& arena, std::span<const geometry::Segment> segments);

}  // namespace sarmap::eval
