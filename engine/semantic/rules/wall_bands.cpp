#include "engine/semantic/rules/wall_bands.hpp"

#include <algorithm>
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
  const auto xs = points.x(), ys = points.y();
  const auto other = static_cast<std::uint8_t>(ClassId::Other), wall = static_cast<std::uint8_t>(ClassId::Wall);
  const auto labels = points.labels();
  const double inv = 1.0 / s.column;

  // Columns holding other or wall, each judged with its patch.
  struct ColumnState {
    std::int8_t verdict = -1;  // -1 unjudged, 0 box-sized, 1 wall
    bool holds_other = false;
  };
  // Each column's state, by its index in the table.
  FlatKeyMap<ColumnState> column_states;
  std::vector<ColumnState>& columns = column_states.values();
  // Each point's column index (kAbsent where it has none), for the last pass.
  std::vector<std::uint32_t> column_of(points.size(), FlatKeyIndex::kAbsent);
  for (std::size_t p = 0; p < points.size(); ++p) {
    if ((labels[p] != other && labels[p] != wall) || !in_reach(xs[p], ys[p])) continue;
    const std::uint32_t c = column_states.try_emplace(grid_keys::column_key_of(xs[p], ys[p], inv)).index;
    columns[c].holds_other = columns[c].holds_other || labels[p] == other;
    column_of[p] = c;
  }
  // Patches are the 8-connected components of the columns, so the order
  // they are walked in changes none of them.
  std::vector<Column> patch;
  std::vector<std::uint32_t> members;
  std::size_t wall_columns = 0;
  for (std::uint32_t start = 0; start < columns.size(); ++start) {
    if (columns[start].verdict >= 0) continue;
    patch.clear(), members.clear();
    columns[start].verdict = 0;
    members.push_back(start);
    bool holds_other = columns[start].holds_other;
    for (std::size_t i = 0; i < members.size(); ++i) {
      const std::uint64_t key = column_states.keys()[members[i]];
      const std::int64_t cx = grid_keys::column_x(key), cy = grid_keys::column_y(key);
      patch.push_back({cx, cy});
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const std::uint32_t c = column_states.index_of(grid_keys::column_key(cx + dx, cy + dy));
          if (c == FlatKeyIndex::kAbsent || columns[c].verdict >= 0) continue;
          columns[c].verdict = 0;
          holds_other = holds_other || columns[c].holds_other;
          members.push_back(c);
        }
      }
    }
    // A patch of wall labels alone has nothing to change.
    if (holds_other && principal_extent(patch) * s.column >= s.min_length) {
      for (const std::uint32_t c : members) columns[c].verdict = 1;
      wall_columns += members.size();
    }
  }
  if (wall_columns == 0) return 0;

  ClassMove to_wall(points, ClassId::Other, ClassId::Wall);
  std::size_t changed = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (labels[p] != other || column_of[p] == FlatKeyIndex::kAbsent) continue;
    if (columns[column_of[p]].verdict != 1) continue;
    to_wall.apply(p);
    ++changed;
  }
  return changed;
}

}  // namespace sarmap
