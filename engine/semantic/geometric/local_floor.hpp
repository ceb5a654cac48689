// Height of the floor around each point of a scan, for the geometric
// classifier's "raised or not" test. A scan has no room extent, so the floor
// is local: the lowest near-horizontal surface within a window around the
// point's xy column. The window is wider than any ramp, so a platform is
// never taken for the floor it stands on.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "engine/core/point_buffer.hpp"
#include "engine/semantic/surface_normals.hpp"

namespace sarmap {

struct LocalFloorSettings {
  double column = 0.25;              // xy cell, metres
  double window = 1.0;               // half-width of the search window, metres
  double max_floor_slope_deg = 8.0;  // steeper surfaces are not floor candidates
};

class LocalFloor {
 public:
  // Points with a valid near-horizontal normal vote for their column's floor.
  // Points beyond 10 km of the origin are ignored.
  LocalFloor(const PointBuffer& points, const SurfaceNormals& normals, const LocalFloorSettings& settings);

  // Floor height under (x, y): the window's lowest floor candidate, else the
  // scan's lowest tenth of candidates, else the scan's lowest point.
  double height_at(double x, double y) const;
  // Highest point of any kind in the column of (x, y) (lowest() when empty).
  double column_top(double x, double y) const;

 private:
  std::uint64_t column_key(double x, double y) const;

  LocalFloorSettings settings_;
  double inv_column_ = 4.0;
  std::unordered_map<std::uint64_t, float> column_floor_;  // lowest candidate per column
  std::unordered_map<std::uint64_t, float> column_top_;
  std::unordered_map<std::uint64_t, float> window_floor_;  // per column holding points
  double fallback_ = 0.0;
};

}  // namespace sarmap
