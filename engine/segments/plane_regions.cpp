#include "engine/segments/plane_regions.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/core/error.hpp"
#include "engine/core/flat_key_index.hpp"

namespace sarmap::segments {
namespace {

// Two cell indices in one word (offset so negatives pack too).
std::uint64_t cell_key(std::int64_t x, std::int64_t y) {
  constexpr std::int64_t kOffset = std::int64_t{1} << 31;
  return (static_cast<std::uint64_t>(x + kOffset) << 32) | static_cast<std::uint32_t>(y + kOffset);
}

}  // namespace

std::vector<std::vector<std::uint32_t>> plane_regions(std::span<const Eigen::Vector2d> points, double cell) {
  if (!(cell > 0) || !std::isfinite(cell)) {
    throw Error(ErrorCode::InvalidArgument, "region growing: cell size must be > 0, got " + std::to_string(cell));
  }
  const std::size_t n = points.size();
  // Cells numbered in the order of their first point; the flood fill starts
  // from them in that order, so region numbers do not depend on hashing.
  FlatKeyIndex cells(n / 2 + 16);
  std::vector<std::int64_t> cx(n), cy(n);
  std::vector<std::uint32_t> cell_of(n);
  for (std::size_t i = 0; i < n; ++i) {
    cx[i] = static_cast<std::int64_t>(std::floor(points[i].x() / cell));
    cy[i] = static_cast<std::int64_t>(std::floor(points[i].y() / cell));
    cell_of[i] = cells.find_or_insert(cell_key(cx[i], cy[i]));
  }
  const std::size_t cell_count = cells.size();
  std::vector<std::int64_t> cell_x(cell_count), cell_y(cell_count);
  for (std::size_t i = 0; i < n; ++i) {
    cell_x[cell_of[i]] = cx[i];
    cell_y[cell_of[i]] = cy[i];
  }
  constexpr std::uint32_t kUnreached = 0xffffffffu;
  std::vector<std::uint32_t> region_of(cell_count, kUnreached);
  std::vector<std::uint32_t> frontier;
  std::uint32_t regions = 0;
  for (std::uint32_t seed = 0; seed < cell_count; ++seed) {
    if (region_of[seed] != kUnreached) continue;
    region_of[seed] = regions;
    frontier.assign(1, seed);
    while (!frontier.empty()) {
      const std::uint32_t c = frontier.back();
      frontier.pop_back();
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const std::uint32_t next = cells.find(cell_key(cell_x[c] + dx, cell_y[c] + dy));
          if (next != FlatKeyIndex::kAbsent && region_of[next] == kUnreached) {
            region_of[next] = regions;
            frontier.push_back(next);
          }
        }
      }
    }
    ++regions;
  }
  std::vector<std::vector<std::uint32_t>> out(regions);
  for (std::uint32_t i = 0; i < n; ++i) out[region_of[cell_of[i]]].push_back(i);
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return out;
}

}  // namespace sarmap::segments
