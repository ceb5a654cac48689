#include "engine/semantic/geometric/local_floor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "engine/core/error.hpp"
#include "engine/semantic/grid_keys.hpp"

namespace sarmap {

namespace {

constexpr double kWorldLimit = 10'000.0;  // the metric map's coordinate limit

bool in_limits(double x, double y, double z) {
  return std::abs(x) <= kWorldLimit && std::abs(y) <= kWorldLimit && std::abs(z) <= kWorldLimit;
}

}  // namespace

std::uint64_t LocalFloor::column_key(double x, double y) const {
  return grid_keys::column_key_of(x, y, inv_column_);
}

LocalFloor::LocalFloor(const PointBuffer& points, const SurfaceNormals& normals, const LocalFloorSettings& settings)
    : settings_(settings) {
  if (!(settings.column >= 0.01) || !(settings.window >= 0) || !std::isfinite(settings.window)) {
    throw Error(ErrorCode::InvalidArgument, "local floor: column must be >= 0.01 m and window >= 0 m");
  }
  inv_column_ = 1.0 / settings.column;
  const double min_nz = std::cos(settings.max_floor_slope_deg * std::numbers::pi / 180.0);
  std::vector<float> candidates;
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double x = points.x()[p], y = points.y()[p], z = points.z()[p];
    if (!in_limits(x, y, z)) continue;
    lowest = std::min(lowest, z);
    const std::uint64_t key = column_key(x, y);
    auto [top, fresh_top] = column_top_.try_emplace(key, static_cast<float>(z));
    if (!fresh_top) top->second = std::max(top->second, static_cast<float>(z));
    if (!normals.valid[p] || normals.nz[p] < min_nz) continue;
    candidates.push_back(static_cast<float>(z));
    auto [floor, fresh_floor] = column_floor_.try_emplace(key, static_cast<float>(z));
    if (!fresh_floor) floor->second = std::min(floor->second, static_cast<float>(z));
  }
  if (!candidates.empty()) {
    const auto tenth = candidates.begin() + static_cast<std::ptrdiff_t>(candidates.size() / 10);
    std::nth_element(candidates.begin(), tenth, candidates.end());
    fallback_ = *tenth;
  } else {
    fallback_ = std::isfinite(lowest) ? lowest : 0.0;
  }
  // The window minimum of every column that holds points, computed once.
  const auto reach = static_cast<std::int64_t>(std::ceil(settings.window * inv_column_));
  for (const auto& [key, top] : column_top_) {
    const std::int64_t ci = grid_keys::column_x(key), cj = grid_keys::column_y(key);
    float best = std::numeric_limits<float>::infinity();
    for (std::int64_t di = -reach; di <= reach; ++di)
      for (std::int64_t dj = -reach; dj <= reach; ++dj) {
        const auto it = column_floor_.find(grid_keys::column_key(ci + di, cj + dj));
        if (it != column_floor_.end()) best = std::min(best, it->second);
      }
    window_floor_[key] = std::isfinite(best) ? best : static_cast<float>(fallback_);
  }
}

double LocalFloor::height_at(double x, double y) const {
  const auto it = window_floor_.find(column_key(x, y));
  return it != window_floor_.end() ? it->second : fallback_;
}

double LocalFloor::column_top(double x, double y) const {
  const auto it = column_top_.find(column_key(x, y));
  return it != column_top_.end() ? it->second : std::numeric_limits<double>::lowest();
}

}  // namespace sarmap
