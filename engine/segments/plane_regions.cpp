#include "engine/segments/plane_regions.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::segments {
namespace {

struct Cell {
  std::int64_t x, y;
  friend auto operator<=>(const Cell&, const Cell&) = default;
};

}  // namespace

std::vector<std::vector<std::uint32_t>> plane_regions(std::span<const Eigen::Vector2d> points, double cell) {
  if (!(cell > 0) || !std::isfinite(cell)) {
    throw Error(ErrorCode::InvalidArgument, "region growing: cell size must be > 0, got " + std::to_string(cell));
  }
  const std::size_t n = points.size();
  // Points sorted by cell; each distinct cell is a node of the flood fill.
  std::vector<std::pair<Cell, std::uint32_t>> by_cell(n);
  for (std::size_t i = 0; i < n; ++i) {
    by_cell[i] = {{static_cast<std::int64_t>(std::floor(points[i].x() / cell)),
                   static_cast<std::int64_t>(std::floor(points[i].y() / cell))},
                  static_cast<std::uint32_t>(i)};
  }
  std::sort(by_cell.begin(), by_cell.end());
  std::vector<Cell> cells;
  std::vector<std::size_t> first;  // index into by_cell of each cell's first point
  for (std::size_t i = 0; i < n; ++i) {
    if (cells.empty() || cells.back() != by_cell[i].first) {
      cells.push_back(by_cell[i].first);
      first.push_back(i);
    }
  }
  first.push_back(n);
  auto find_cell = [&cells](const Cell& c) -> std::ptrdiff_t {
    const auto it = std::lower_bound(cells.begin(), cells.end(), c);
    return it != cells.end() && *it == c ? it - cells.begin() : -1;
  };

  std::vector<std::vector<std::uint32_t>> regions;
  std::vector<bool> reached(cells.size(), false);
  std::vector<std::size_t> frontier;
  for (std::size_t seed = 0; seed < cells.size(); ++seed) {
    if (reached[seed]) continue;
    reached[seed] = true;
    frontier.assign(1, seed);
    std::vector<std::uint32_t> region;
    while (!frontier.empty()) {
      const std::size_t c = frontier.back();
      frontier.pop_back();
      for (std::size_t i = first[c]; i < first[c + 1]; ++i) region.push_back(by_cell[i].second);
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const std::ptrdiff_t next = find_cell({cells[c].x + dx, cells[c].y + dy});
          if (next >= 0 && !reached[static_cast<std::size_t>(next)]) {
            reached[static_cast<std::size_t>(next)] = true;
            frontier.push_back(static_cast<std::size_t>(next));
          }
        }
      }
    }
    std::sort(region.begin(), region.end());
    regions.push_back(std::move(region));
  }
  std::sort(regions.begin(), regions.end(), [](const auto& a, const auto& b) {
    return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
  });
  return regions;
}

}  // namespace sarmap::segments
