// True shortest paths on the drivable grid (the default arena's eval pairs, a
// corridor, a doorway, a closed wall, ramps onto platforms) and the exact
// test of segments against the arena's walls and boxes.
#include "engine/eval/truth_paths.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::eval {
namespace {

sim::Arena arena_with(const std::string& elements, const std::string& size = "[6, 4, 2]") {
  return sim::parse_arena(R"({"name": "t", "bounds": {"min": [0, 0, 0], "max": )" + size + R"(}, "floor": true,
    "elements": [)" + elements + R"(],
    "trajectory": {"waypoints": [[0.5, 2], [3.5, 2]], "height": 0.5, "frames": 2, "pitch_deg": 0},
    "sensor": {"type": "depth_camera", "width": 8, "height": 6, "fx": 7, "fy": 7, "cx": 4, "cy": 3,
               "min_range": 0.1, "max_range": 6, "noise": "none"}})",
                          "t.json", ".");
}

// Every step of the path is a move the grid allows, and the length adds up.
void expect_drivable(const DrivableGrid& grid, const TruthPath& path) {
  ASSERT_TRUE(path.found);
  ASSERT_GE(path.points.size(), 2u);
  double length = 0;
  for (std::size_t i = 1; i < path.points.size(); ++i) {
    const Eigen::Vector3d& a = path.points[i - 1];
    const Eigen::Vector3d& b = path.points[i];
    length += (b - a).norm();
    const auto ca = grid.cell_of(a.x(), a.y()), cb = grid.cell_of(b.x(), b.y());
    ASSERT_TRUE(ca && cb);
    EXPECT_FALSE(grid.blocked(*cb)) << b.transpose();
    if (!(*ca == *cb)) {
      EXPECT_TRUE(grid.passable(*ca, *cb)) << a.transpose() << " -> " << b.transpose();
    }
  }
  EXPECT_NEAR(path.length, length, 1e-9);
  // The any-angle path keeps the ends, never runs longer, and each of its
  // lines is drivable between its cell centres.
  const auto& any = path.any_angle_points;
  ASSERT_GE(any.size(), 2u);
  EXPECT_EQ(any.front(), path.points.front());
  EXPECT_EQ(any.back(), path.points.back());
  EXPECT_LE(path.any_angle_length, path.length + 1e-9);
  for (std::size_t i = 2; i + 1 < any.size(); ++i) EXPECT_TRUE(line_passable(grid, any[i - 1], any[i]));
}

TEST(TruthPaths, DefaultArenaEvalPairs) {
  const sim::Arena arena = sim::load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  ASSERT_EQ(arena.eval_pairs.size(), 2u);
  const DrivableGrid grid(arena);
  EXPECT_EQ(grid.width(), 120);
  EXPECT_EQ(grid.height(), 80);
  // The first goal is on the platform, which no ramp reaches.
  const auto& [s0, g0] = arena.eval_pairs[0];
  const TruthPath first = shortest_path(grid, s0, g0);
  EXPECT_FALSE(first.found);
  EXPECT_EQ(first.status, PathStatus::Unreachable);
  EXPECT_TRUE(first.points.empty());
  // The second stays on the floor.
  const auto& [s1, g1] = arena.eval_pairs[1];
  const TruthPath second = shortest_path(grid, s1, g1);
  EXPECT_EQ(second.status, PathStatus::Found);
  expect_drivable(grid, second);
  EXPECT_GE(second.length, (g1 - s1).norm());
  EXPECT_LT(second.length, 1.5 * (g1 - s1).norm());
  // On the floor, or at most a step up the low end of the ramp it passes.
  for (const Eigen::Vector3d& p : second.points) EXPECT_LE(p.z(), 0.05) << p.transpose();
  EXPECT_EQ(path_status_name(first.status), "unreachable");
}

TEST(TruthPaths, StraightCorridorIsTheStraightDistance) {
  const sim::Arena arena = arena_with(R"(
    {"type": "wall", "from": [0.5, 1], "to": [5.5, 1], "height": 1, "thickness": 0.1},
    {"type": "wall", "from": [0.5, 2], "to": [5.5, 2], "height": 1, "thickness": 0.1})");
  const DrivableGrid grid(arena);
  // Cell centres: the path runs along one row of cells.
  const Eigen::Vector3d start(1.025, 1.525, 0), goal(4.525, 1.525, 0);
  const TruthPath path = shortest_path(grid, start, goal);
  expect_drivable(grid, path);
  EXPECT_NEAR(path.length, 3.5, 1e-9);
  EXPECT_NEAR(path.any_angle_length, 3.5, 1e-9);
  EXPECT_EQ(path.any_angle_points.size(), 2u);
  // The robot's radius keeps it 0.2 m (to within half a cell) from the walls' faces.
  EXPECT_FALSE(grid.blocked(*grid.cell_of(1.0, 1.28)));
  EXPECT_TRUE(grid.blocked(*grid.cell_of(1.0, 1.22)));
  EXPECT_FALSE(grid.blocked(*grid.cell_of(1.0, 1.72)));
  EXPECT_TRUE(grid.blocked(*grid.cell_of(1.0, 1.78)));
  EXPECT_TRUE(grid.obstacle(*grid.cell_of(1.0, 1.0)));
  // A start inside a wall's reach, and one off the grid.
  EXPECT_EQ(shortest_path(grid, {1.0, 1.1, 0}, goal).status, PathStatus::StartBlocked);
  EXPECT_EQ(shortest_path(grid, start, {1.0, 2.1, 0}).status, PathStatus::GoalBlocked);
  EXPECT_EQ(shortest_path(grid, {-1, 1.5, 0}, goal).status, PathStatus::OutsideArena);
  EXPECT_EQ(shortest_path(grid, {1.0, 1.5, 0.5}, goal).status, PathStatus::OffSurface);
}

// A wall across the room at x = 3 with a door from y = 1.65 to 2.35.
const char* kDoorway = R"(
    {"type": "wall", "from": [3, 0], "to": [3, 1.6], "height": 1, "thickness": 0.1},
    {"type": "wall", "from": [3, 2.4], "to": [3, 4], "height": 1, "thickness": 0.1})";

TEST(TruthPaths, DoorwayPathBendsThroughTheDoor) {
  const sim::Arena arena = arena_with(kDoorway);
  const DrivableGrid grid(arena);
  const Eigen::Vector3d start(1, 0.6, 0), goal(5, 0.6, 0);
  const TruthPath path = shortest_path(grid, start, goal);
  expect_drivable(grid, path);
  // Through the door, at least 0.2 m from its jambs.
  bool through = false;
  for (const Eigen::Vector3d& p : path.points) {
    if (std::abs(p.x() - 3) < 0.03) {
      through = true;
      EXPECT_GE(p.y(), 1.85 - 0.025) << p.transpose();
      EXPECT_LE(p.y(), 2.15 + 0.025) << p.transpose();
    }
  }
  EXPECT_TRUE(through);
  // The shortest line around the blocked cells by the jamb (within 0.225 m of
  // the centres of the wall's cells at (2.975, 1.625) and (3.025, 1.625)):
  // tangent from the start to the first circle, over both, tangent to the goal.
  const double r = 0.225, d = std::hypot(2.975 - 1, 1.625 - 0.6);
  const double tangent = std::sqrt(d * d - r * r);
  const double wrap = std::numbers::pi / 2 + std::atan2(1.625 - 0.6, 2.975 - 1) - std::acos(r / d);
  const double around = 2 * (tangent + r * wrap) + 0.05;
  // Theta*'s corners sit on free cell centres, a little outside the circles.
  EXPECT_GT(path.any_angle_length, around - 0.01);
  EXPECT_LT(path.any_angle_length, 1.015 * around);
  // The 8-connected path runs longer, by less than 8.3%.
  EXPECT_GT(path.length, path.any_angle_length + 0.1);
  EXPECT_LT(path.length, 1.083 * around);
  // The straight line crosses the wall; no step of the path does.
  std::vector<geometry::Segment> segments{{start + Eigen::Vector3d(0, 0, 0.3), goal + Eigen::Vector3d(0, 0, 0.3)}};
  for (std::size_t i = 1; i < path.points.size(); ++i) {
    segments.push_back({path.points[i - 1] + Eigen::Vector3d(0, 0, 0.3), path.points[i] + Eigen::Vector3d(0, 0, 0.3)});
  }
  const std::vector<bool> crossing = segments_crossing_walls(arena, segments);
  ASSERT_EQ(crossing.size(), segments.size());
  EXPECT_TRUE(crossing[0]);
  for (std::size_t i = 1; i < crossing.size(); ++i) EXPECT_FALSE(crossing[i]) << i;
}

TEST(TruthPaths, ClosedWallHasNoPath) {
  const TruthPath path = truth_path(
      arena_with(R"({"type": "wall", "from": [3, 0], "to": [3, 4], "height": 1, "thickness": 0.1})"), {1, 2, 0},
      {5, 2, 0});
  EXPECT_FALSE(path.found);
  EXPECT_EQ(path.status, PathStatus::Unreachable);
  // A wall thinner than a cell blocks too.
  EXPECT_FALSE(truth_path(arena_with(R"({"type": "wall", "from": [3.01, 0], "to": [3.01, 4], "height": 1,
                                         "thickness": 0.02})"),
                          {1, 2, 0}, {5, 2, 0})
                   .found);
  // A box across the room is an obstacle like a wall; a mat lower than a step is not.
  EXPECT_FALSE(truth_path(arena_with(R"({"type": "box", "center": [3, 2, 0.3], "size": [0.3, 4.2, 0.6]})"),
                          {1, 2, 0}, {5, 2, 0})
                   .found);
  EXPECT_TRUE(truth_path(arena_with(R"({"type": "box", "center": [3, 2, 0.01], "size": [0.3, 4.2, 0.02]})"),
                         {1, 2, 0}, {5, 2, 0})
                  .found);
}

// A 0.25 m platform from x = 3.5 to 4.5, and a ramp rising 0.25 m over 1 m
// (14.04 degrees) from x = 2.5 that touches its west side.
const char* kPlatform = R"({"type": "flat_ramp", "center": [4, 2], "size": [1, 1], "height": 0.25})";
const char* kRampToPlatform =
    R"({"type": "inclined_ramp", "center": [3, 2], "length": 1, "width": 0.8, "angle_deg": 14.036243467926479})";

TEST(TruthPaths, RampClimbsOntoThePlatformItTouches) {
  const sim::Arena arena = arena_with(std::string(kPlatform) + ", " + kRampToPlatform);
  const DrivableGrid grid(arena);
  EXPECT_NEAR(grid.surface(*grid.cell_of(4.0, 2.0)), 0.25, 1e-6);
  EXPECT_NEAR(grid.surface(*grid.cell_of(3.0, 2.0)), 0.125 + 0.025 * 0.25, 1e-6);  // cell centre x = 3.025
  // Cell centres on one row: floor, ramp and platform top.
  const Eigen::Vector3d start(1.025, 2.025, 0), goal(4.025, 2.025, 0.25);
  const TruthPath path = shortest_path(grid, start, goal);
  expect_drivable(grid, path);
  double top = 0;
  for (const Eigen::Vector3d& p : path.points) top = std::max(top, p.z());
  EXPECT_NEAR(top, 0.25, 1e-6);
  // 3 m with the climb's extra length (to the cells' resolution of the ramp's ends).
  EXPECT_NEAR(path.length, 2.0 + std::hypot(1.0, 0.25), 0.002);
  // And down again, the same way.
  EXPECT_NEAR(shortest_path(grid, goal, start).length, path.length, 1e-9);
}

TEST(TruthPaths, PlatformWithoutARampCannotBeEntered) {
  const Eigen::Vector3d start(1, 2, 0), goal(4, 2, 0.25);
  EXPECT_EQ(truth_path(arena_with(kPlatform), start, goal).status, PathStatus::Unreachable);
  // A ramp that stops 0.1 m below the platform leaves a step too high to drive.
  const TruthPath low = truth_path(
      arena_with(std::string(kPlatform) + R"(, {"type": "inclined_ramp", "center": [3, 2], "length": 1, "width": 0.8,
                                                "angle_deg": 8.530765609948133})"),
      start, goal);
  EXPECT_EQ(low.status, PathStatus::Unreachable);
  // A larger step setting lets it up.
  DrivableSettings tall;
  tall.max_step = 0.12;
  EXPECT_TRUE(truth_path(arena_with(std::string(kPlatform) + R"(, {"type": "inclined_ramp", "center": [3, 2],
                                     "length": 1, "width": 0.8, "angle_deg": 8.530765609948133})"),
                         start, goal, tall)
                  .found);
}

TEST(TruthPaths, SegmentsAgainstWallsAndBoxesAreExact) {
  const sim::Arena arena = arena_with(std::string(kDoorway) +
                                      R"(, {"type": "box", "center": [1, 3, 0.25], "size": [0.4, 0.4, 0.5], "yaw_deg": 45})");
  const double top = 1.0;
  const std::vector<geometry::Segment> segments{
      {{2, 1, top + 1e-9}, {4, 1, top + 1e-9}},  // just over the wall
      {{2, 1, top - 1e-9}, {4, 1, top - 1e-9}},  // just under its top
      {{2, 2, 0.5}, {4, 2, 0.5}},                // through the door
      {{2, 1.6 + 0.05 + 1e-9, 0.5}, {4, 1.6 + 0.05 + 1e-9, 0.5}},  // grazing past the jamb
      {{3, 0.5, top}, {3, 1.0, top}},            // along the wall's top: touching counts
      {{0, 3, 0.2}, {2, 3, 0.2}},                // through the box
      {{1 + 0.2 * std::sqrt(2.0) + 1e-6, 3, 0.2}, {1 + 0.2 * std::sqrt(2.0) + 1e-6, 3.5, 0.2}},  // past its corner
      {{1, 1, 0.5}, {1, 1, 0.5}},                // a point in the open
  };
  const std::vector<bool> crossing = segments_crossing_walls(arena, segments);
  EXPECT_EQ(crossing, (std::vector<bool>{false, true, false, false, true, true, false, false}));
  EXPECT_EQ(wall_and_box_solids(arena).size(), 3u);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<geometry::Segment> bad{{{0, 0, 0}, {nan, 0, 0}}};
  EXPECT_THROW(segments_crossing_walls(arena, bad), Error);
}

TEST(TruthPaths, SettingsAreChecked) {
  const sim::Arena arena = arena_with("");
  DrivableSettings s;
  s.cell = 0;
  EXPECT_THROW(DrivableGrid(arena, s), Error);
  s = {};
  s.robot_radius = -1;
  EXPECT_THROW(DrivableGrid(arena, s), Error);
  s = {};
  s.max_step = std::numeric_limits<double>::infinity();
  EXPECT_THROW(DrivableGrid(arena, s), Error);
  // No robot radius: only the obstacle cells themselves are blocked.
  s = {};
  s.robot_radius = 0;
  const DrivableGrid open(arena_with(kDoorway), s);
  EXPECT_TRUE(open.blocked(*open.cell_of(3.0, 1.0)));
  EXPECT_FALSE(open.blocked(*open.cell_of(3.1, 1.0)));
}

}  // namespace
}  // namespace sarmap::eval
