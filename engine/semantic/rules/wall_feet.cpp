#include "engine/semantic/rules/wall_feet.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/core/flat_key_map.hpp"
#include "engine/semantic/grid_keys.hpp"
#include "engine/semantic/rules/class_move.hpp"
#include "engine/semantic/rules/finite_points.hpp"

namespace sarmap {

namespace {

using grid_keys::in_reach;

// The terrain points of one column: their count and height sum.
struct FloorSum {
  std::size_t points = 0;
  double height_sum = 0.0;
};

}  // namespace

void validate(const WallFootSettings& s) {
  if (!(s.column >= 0.01) || !std::isfinite(s.column)) {
    throw Error(ErrorCode::InvalidArgument, "wall feet: the column must be at least 0.01 m");
  }
  if (!(s.tolerance >= 0.0) || !std::isfinite(s.tolerance)) {
    throw Error(ErrorCode::InvalidArgument, "wall feet: the tolerance must be finite and >= 0, got " +
                                                std::to_string(s.tolerance));
  }
  if (s.min_floor_points == 0) {
    throw Error(ErrorCode::InvalidArgument, "wall feet: min_floor_points must be at least 1");
  }
}

std::size_t label_wall_feet(PointBuffer& points, const WallFootSettings& s) {
  validate(s);
  if (!s.enabled || !points.has_labels()) return 0;
  require_finite_points(points, "wall feet");
  const auto xs = points.x(), ys = points.y(), zs = points.z();
  const auto terrain = static_cast<std::uint8_t>(ClassId::Terrain), wall = static_cast<std::uint8_t>(ClassId::Wall);
  const auto labels = points.labels();
  const double inv = 1.0 / s.column;

  // The floor's columns, each with its sum.
  FlatKeyMap<FloorSum> floor;
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (labels[p] != terrain || !in_reach(xs[p], ys[p])) continue;
    FloorSum& column = floor[grid_keys::column_key_of(xs[p], ys[p], inv)];
    ++column.points;
    column.height_sum += zs[p];
  }
  if (floor.empty()) return 0;

  ClassMove to_terrain(points, ClassId::Wall, ClassId::Terrain);
  std::size_t changed = 0;
  // Neighbouring points (a depth image's row, a ring) mostly share a
  // column: the floor around it is summed once for the run of them.
  std::int64_t last_cx = 0, last_cy = 0;
  bool summed = false;
  FloorSum around;
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (labels[p] != wall || !in_reach(xs[p], ys[p])) continue;
    const std::int64_t cx = grid_keys::index(xs[p], inv), cy = grid_keys::index(ys[p], inv);
    if (!summed || cx != last_cx || cy != last_cy) {
      around = {};
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const FloorSum* column = floor.find(grid_keys::column_key(cx + dx, cy + dy));
          if (column == nullptr) continue;
          around.points += column->points;
          around.height_sum += column->height_sum;
        }
      }
      last_cx = cx, last_cy = cy, summed = true;
    }
    if (around.points < s.min_floor_points) continue;
    const double floor_height = around.height_sum / static_cast<double>(around.points);
    if (!(zs[p] <= floor_height + s.tolerance)) continue;
    to_terrain.apply(p);
    ++changed;
  }
  return changed;
}

}  // namespace sarmap
