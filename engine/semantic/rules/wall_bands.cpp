#include "engine/semantic/rules/wall_bands.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/semantic/grid_keys.hpp"
#include "engine/semantic/rules/class_move.hpp"
#include "engine/semantic/rules/finite_points.hpp"

namespace sarmap {

namespace {

using grid_keys::in_reach;

struct Column {
  std::int64_t cx, cy;
};

// The extent, in columns, of a patch along its principal axis (the
// covariance of the column centres: a patch at 45 degrees measures its
// length, not its bounding box).
double principal_extent(const std::vector<Column>& patch) {
  const double n = static_cast<double>(patch.size());
  double mx = 0, my = 0;
  for (const Column& c : patch) mx += static_cast<double>(c.cx), my += static_cast<double>(c.cy);
  mx /= n, my /= n;
  double sxx = 0, sxy = 0, syy = 0;
  for (const Column& c : patch) {
    const double dx = static_cast<double>(c.cx) - mx, dy = static_cast<double>(c.cy) - my;
    sxx += dx * dx, sxy += dx * dy, syy += dy * dy;
  }
  const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  const double ux = std::cos(angle), uy = std::sin(angle);
  double low = 0, high = 0;
  for (const Column& c : patch) {
    const double along = (static_cast<double>(c.cx) - mx) * ux + (static_cast<double>(c.cy) - my) * uy;
    low = std::min(low, along), high = std::max(high, along);
  }
  return high - low + 1.0;  // centre to centre, plus one column
}

}  // namespace

void validate(const WallBandSettings& s) {
  if (!(s.column >= 0.01) || !std::isfinite(s.column)) {
    throw Error(ErrorCode::InvalidArgument, "wall bands: the column must be at least 0.01 m");
  }
  if (!(s.min_length > 0.0) || !std::isfinite(s.min_length)) {
    throw Error(ErrorCode::InvalidArgument, "wall bands: the length must be positive, got " +
                                                std::to_string(s.min_length));
  }
}

std::size_t label_wall_bands(PointBuffer& points, const WallBandSettings& s) {
  validate(s);
  if (!s.enabled || !points.has_labels()) return 0;
  require_finite_points(points, "wall bands");
  const auto xs = points.x(), ys = points.y(), zs = points.z();
  const auto other = static_cast<std::uint8_t>(ClassId::Other), wall = static_cast<std::uint8_t>(ClassId::Wall);
  const auto labels = points.labels();
  const double inv = 1.0 / s.column;

  // Columns holding other or wall, each judged with its patch.
  struct ColumnState {
    std::int8_t verdict = -1;  // -1 unjudged, 0 box-sized, 1 wall
    bool holds_other = false;
  };
  std::unordered_map<std::uint64_t, ColumnState> columns;
  for (std::size_t p = 0; p < points.size(); ++p) {
    if ((labels[p] != other && labels[p] != wall) || !in_reach(xs[p], ys[p])) continue;
    ColumnState& column = columns[grid_keys::column_key_of(xs[p], ys[p], inv)];
    column.holds_other = column.holds_other || labels[p] == other;
  }
  std::vector<Column> patch;
  std::vector<std::uint64_t> keys;
  std::size_t wall_columns = 0;
  for (auto& [start, state] : columns) {
    if (state.verdict >= 0) continue;
    patch.clear(), keys.clear();
    state.verdict = 0;
    keys.push_back(start);
    bool holds_other = state.holds_other;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const std::int64_t cx = grid_keys::column_x(keys[i]), cy = grid_keys::column_y(keys[i]);
      patch.push_back({cx, cy});
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const auto it = columns.find(grid_keys::column_key(cx + dx, cy + dy));
          if (it == columns.end() || it->second.verdict >= 0) continue;
          it->second.verdict = 0;
          holds_other = holds_other || it->second.holds_other;
          keys.push_back(it->first);
        }
      }
    }
    // A patch of wall labels alone has nothing to change.
    if (holds_other && principal_extent(patch) * s.column >= s.min_length) {
      for (std::uint64_t k : keys) columns[k].verdict = 1;
      wall_columns += keys.size();
    }
  }
  if (wall_columns == 0) return 0;

  ClassMove to_wall(points, ClassId::Other, ClassId::Wall);
  std::size_t changed = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (labels[p] != other || !in_reach(xs[p], ys[p])) continue;
    if (columns.find(grid_keys::column_key_of(xs[p], ys[p], inv))->second.verdict != 1) continue;
    to_wall.apply(p);
    ++changed;
  }
  return changed;
}

}  // namespace sarmap
