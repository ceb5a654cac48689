// The ground truth of where a robot can drive in an arena, as a fine 2.5-D
// grid: per cell the walkable surface height (floor, ramp deck, platform top)
// and whether a wall, box or other obstacle lies within the robot's radius.
// What the true shortest paths (truth_paths.hpp) are searched on.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "engine/sim/arena.hpp"

namespace sarmap::eval {

struct DrivableSettings {
  double cell = 0.05;          // metres
  double robot_radius = 0.2;   // metres: no obstacle may come closer to the robot's centre
  double max_step = 0.05;      // metres: the largest height change between neighbouring cells
  // A start or goal more than this above or below the surface under it is on
  // no surface the grid knows (metres).
  double surface_tolerance = 0.1;
};

// Throws sarmap::Error (InvalidArgument) naming the first setting out of range.
void validate(const DrivableSettings& settings);

struct GridCell {
  std::int32_t x = 0, y = 0;
  friend bool operator==(const GridCell&, const GridCell&) = default;
};

class DrivableGrid {
 public:
  // Rasterises the arena's meshes at the cell centres: terrain, inclined and
  // flat ramp faces that face up give the walkable surface (the highest one);
  // faces of any other class give obstacles, which count where they reach
  // higher than max_step above the surface. A vertical obstacle face marks
  // every cell its footprint crosses, so a wall thinner than a cell is not
  // lost. A cell is blocked when an obstacle cell's centre lies within
  // robot_radius + cell / 2 of its centre (the obstacle's edge lies about half
  // a cell beyond the centre), or when it has no surface. Throws like validate.
  explicit DrivableGrid(const sim::Arena& arena, const DrivableSettings& settings = {});

  const DrivableSettings& settings() const { return settings_; }
  std::int32_t width() const { return nx_; }
  std::int32_t height() const { return ny_; }

  bool inside(const GridCell& c) const { return c.x >= 0 && c.y >= 0 && c.x < nx_ && c.y < ny_; }
  // The cell holding (x, y); nullopt outside the arena's bounds.
  std::optional<GridCell> cell_of(double x, double y) const;
  // The cell's centre at its surface height (NaN height without a surface).
  Eigen::Vector3d center(const GridCell& c) const;
  // NaN where no walkable surface lies under the cell's centre.
  double surface(const GridCell& c) const { return surface_[index(c)]; }
  bool obstacle(const GridCell& c) const { return obstacle_[index(c)] != 0; }
  bool blocked(const GridCell& c) const { return blocked_[index(c)] != 0; }
  // Whether the robot can move from `a` to its 8-neighbour `b`: both free,
  // heights within max_step, and for a diagonal move both cells it passes
  // between free and within max_step of `a` (no cutting a corner).
  bool passable(const GridCell& a, const GridCell& b) const;

  std::size_t index(const GridCell& c) const {
    return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(c.x);
  }

 private:
  bool step_ok(const GridCell& a, const GridCell& b) const;

  DrivableSettings settings_;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();  // the bounds' lower corner
  std::int32_t nx_ = 0, ny_ = 0;
  std::vector<double> surface_;
  std::vector<std::uint8_t> obstacle_, blocked_;
};

}  // namespace sarmap::eval
