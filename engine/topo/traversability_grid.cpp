#include "engine/topo/traversability_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/core/vector_headroom.hpp"

namespace sarmap::topo {
namespace {

bool walkable(ClassId label) {
  return label == ClassId::Terrain || label == ClassId::InclinedRamp || label == ClassId::FlatRamp;
}

// Grid cells [x0, x1] x [y0, y1], inclusive.
struct CellRect {
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
  bool empty() const { return x0 > x1 || y0 > y1; }
  int width() const { return x1 - x0 + 1; }
  bool contains(int x, int y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(x - x0) + static_cast<std::size_t>(width()) * static_cast<std::size_t>(y - y0);
  }
};

CellRect grown(const CellRect& r, int by, const PlanningGrid& grid) {
  return {std::max(r.x0 - by, 0), std::min(r.x1 + by, grid.width() - 1), std::max(r.y0 - by, 0),
          std::min(r.y1 + by, grid.height() - 1)};
}

int reach_of(const TopoSettings& settings, double res) {
  return static_cast<int>(std::floor(settings.robot_radius / res + 1e-9));
}

// Computes the cells of `target` of a grid with the columns' extent from the
// columns alone. A cell's value depends on the columns within reach + 2 of
// it (a gap's two neighbours, a rim's neighbours, the robot's radius), so
// only those are read, and every cell outside `target` is left as it is.
void compute_cells(TraversabilityGrid& out, const VoxelColumns& columns, const TopoSettings& settings,
                   const CellRect& target, TraversabilityScratch& scratch) {
  const double res = columns.resolution;
  const int reach = reach_of(settings, res);
  const int width = out.grid.width(), height = out.grid.height();
  const CellRect read = grown(target, reach + 2, out.grid);
  const std::size_t cells = static_cast<std::size_t>(read.width()) * static_cast<std::size_t>(read.y1 - read.y0 + 1);
  std::vector<CellState>& seen = scratch.seen;
  std::vector<float>& ground = scratch.ground;
  std::vector<ClassId>& ground_class = scratch.ground_class;
  assign_with_headroom(seen, cells, CellState::Unknown);
  assign_with_headroom(ground, cells, std::nanf(""));
  assign_with_headroom(ground_class, cells, ClassId::Unknown);

  // The robot's height in voxels: an occupied voxel closer above a surface
  // than this leaves no room to drive there.
  const auto clearance = static_cast<std::int32_t>(std::ceil(settings.robot_height / res));
  for (int y = read.y0; y <= read.y1; ++y) {
    for (int x = read.x0; x <= read.x1; ++x) {
      const std::size_t c = columns.column(x, y);
      const std::uint32_t begin = columns.start[c], end = columns.start[c + 1];
      if (begin == end) continue;
      const std::size_t i = read.index(x, y);
      seen[i] = CellState::Occupied;
      for (std::uint32_t v = end; v-- > begin;) {
        if (!walkable(columns.label[v])) continue;
        if (v + 1 == end || columns.z[v + 1] - columns.z[v] > clearance) {
          ground[i] = static_cast<float>((columns.z[v] + 0.5) * res);
          ground_class[i] = columns.label[v];
          seen[i] = CellState::Free;
          break;
        }
      }
    }
  }

  // Pinholes and cracks: a cell nobody's ray ended in, between seen ground
  // on two opposite sides at heights within a step, is that ground (a
  // sensor's pixel grid leaves such one-cell gaps, lines of them across a
  // slope). Read from the cells as they were, so gaps never grow.
  std::vector<CellState>& state = scratch.state;
  assign_with_headroom(state, cells, CellState::Unknown);
  std::copy(seen.begin(), seen.end(), state.begin());
  const CellRect filled = grown(target, reach + 1, out.grid);
  for (int y = std::max(filled.y0, 1); y <= std::min(filled.y1, height - 2); ++y) {
    for (int x = std::max(filled.x0, 1); x <= std::min(filled.x1, width - 2); ++x) {
      const std::size_t i = read.index(x, y);
      if (seen[i] != CellState::Unknown) continue;
      for (const auto& [ia, ib] : {std::pair{read.index(x - 1, y), read.index(x + 1, y)},
                                   std::pair{read.index(x, y - 1), read.index(x, y + 1)}}) {
        if (seen[ia] != CellState::Free || seen[ib] != CellState::Free) continue;
        if (std::abs(ground[ia] - ground[ib]) > settings.max_step) continue;
        state[i] = CellState::Free;
        ground[i] = (ground[ia] + ground[ib]) / 2;
        ground_class[i] = ground_class[ia];
        break;
      }
    }
  }

  // The cells as seen and filled, before blocking.
  for (int y = target.y0; y <= target.y1; ++y) {
    for (int x = target.x0; x <= target.x1; ++x) {
      const std::size_t i = read.index(x, y), o = out.grid.index_of({x, y});
      out.grid.cells()[o] = state[i];
      out.ground[o] = ground[i];
      out.ground_class[o] = ground_class[i];
      out.near_drop[o] = 0;
    }
  }

  // Drops: a free cell more than a step above a free neighbour is a rim.
  // Blocked cells (occupied ones and rims) grow by the robot's radius (cell
  // centres within it) into the target.
  std::vector<std::pair<int, int>> disk;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      if ((dx * dx + dy * dy) * res * res <= settings.robot_radius * settings.robot_radius + 1e-12) disk.emplace_back(dx, dy);
    }
  }
  const CellRect blocking = grown(target, reach, out.grid);
  for (int y = blocking.y0; y <= blocking.y1; ++y) {
    for (int x = blocking.x0; x <= blocking.x1; ++x) {
      const std::size_t i = read.index(x, y);
      bool rim = false;
      if (state[i] == CellState::Free) {
        for (int dy = -1; dy <= 1 && !rim; ++dy) {
          for (int dx = -1; dx <= 1 && !rim; ++dx) {
            if (!out.grid.contains({x + dx, y + dy})) continue;
            const std::size_t n = read.index(x + dx, y + dy);
            rim = state[n] == CellState::Free && ground[i] - ground[n] > settings.max_step;
          }
        }
      }
      if (!rim && state[i] != CellState::Occupied) continue;
      for (const auto& [dx, dy] : disk) {
        if (!target.contains(x + dx, y + dy)) continue;
        const std::size_t o = out.grid.index_of({x + dx, y + dy});
        out.grid.cells()[o] = CellState::Occupied;
        if (rim) out.near_drop[o] = 1;
      }
    }
  }
}

bool same_extent(const TraversabilityGrid& grid, const VoxelColumns& columns) {
  const double res = columns.resolution;
  return grid.grid.width() == columns.width && grid.grid.height() == columns.height &&
         grid.grid.origin() == Eigen::Vector2d(columns.x0 * res, columns.y0 * res);
}

// `out` laid on the columns' extent, every cell unknown with no ground.
void make_blank(TraversabilityGrid& out, const VoxelColumns& columns) {
  const double res = columns.resolution;
  out.grid.reset(columns.width, columns.height, res, Eigen::Vector2d(columns.x0 * res, columns.y0 * res),
                 CellState::Unknown);
  const std::size_t cells = out.grid.cells().size();
  assign_with_headroom(out.ground, cells, std::nanf(""));
  assign_with_headroom(out.ground_class, cells, ClassId::Unknown);
  assign_with_headroom(out.near_drop, cells, std::uint8_t{0});
}

// Lays the old grid's cells into `out`, on the columns' extent: the cells farther than
// `margin` from both grids' edges keep their values (their columns lie inside
// both extents, and an edge changes what a cell near it can become: a gap on
// the edge is never filled, a neighbour outside never a rim's), the others
// are computed. Columns that changed are the caller's to compute.
void relay(const TraversabilityGrid& old, TraversabilityGrid& out, const VoxelColumns& columns,
           const TopoSettings& settings, int margin, TraversabilityScratch& scratch) {
  make_blank(out, columns);
  const double res = columns.resolution;
  const auto old_x0 = static_cast<std::int32_t>(std::lround(old.grid.origin().x() / res));
  const auto old_y0 = static_cast<std::int32_t>(std::lround(old.grid.origin().y() / res));
  // In the new grid's cells.
  const int dx = old_x0 - columns.x0, dy = old_y0 - columns.y0;
  const CellRect keep{std::max(dx, 0) + margin, std::min(dx + old.grid.width(), columns.width) - 1 - margin,
                      std::max(dy, 0) + margin, std::min(dy + old.grid.height(), columns.height) - 1 - margin};
  const CellRect all{0, columns.width - 1, 0, columns.height - 1};
  if (keep.empty()) {
    compute_cells(out, columns, settings, all, scratch);
    return;
  }
  for (int y = keep.y0; y <= keep.y1; ++y) {
    const std::size_t from = old.grid.index_of({keep.x0 - dx, y - dy}), to = out.grid.index_of({keep.x0, y});
    const auto n = static_cast<std::size_t>(keep.width());
    std::copy_n(old.grid.cells().begin() + from, n, out.grid.cells().begin() + to);
    std::copy_n(old.ground.begin() + from, n, out.ground.begin() + to);
    std::copy_n(old.ground_class.begin() + from, n, out.ground_class.begin() + to);
    std::copy_n(old.near_drop.begin() + from, n, out.near_drop.begin() + to);
  }
  for (const CellRect& strip : {CellRect{all.x0, all.x1, all.y0, keep.y0 - 1}, CellRect{all.x0, all.x1, keep.y1 + 1, all.y1},
                                CellRect{all.x0, keep.x0 - 1, keep.y0, keep.y1}, CellRect{keep.x1 + 1, all.x1, keep.y0, keep.y1}}) {
    if (!strip.empty()) compute_cells(out, columns, settings, strip, scratch);
  }
}

}  // namespace

TraversabilityGrid traversability_grid(const VoxelColumns& columns, const TopoSettings& settings) {
  validate(settings);
  if (columns.empty()) {
    TraversabilityGrid out;
    out.grid = PlanningGrid(1, 1, columns.resolution, Eigen::Vector2d::Zero());
    out.ground.assign(1, std::nanf(""));
    out.ground_class.assign(1, ClassId::Unknown);
    out.near_drop.assign(1, 0);
    return out;
  }
  TraversabilityGrid out;
  make_blank(out, columns);
  TraversabilityScratch scratch;
  compute_cells(out, columns, settings, {0, columns.width - 1, 0, columns.height - 1}, scratch);
  return out;
}

void update_traversability_grid(TraversabilityGrid& grid, const VoxelColumns& columns, const TopoSettings& settings,
                                const ColumnRect& changed, TraversabilityScratch& scratch) {
  if (columns.empty() || grid.ground.empty() || grid.grid.resolution() != columns.resolution) {
    grid = traversability_grid(columns, settings);
    return;
  }
  const int margin = reach_of(settings, columns.resolution) + 2;
  if (!same_extent(grid, columns)) {
    relay(grid, scratch.spare, columns, settings, margin, scratch);
    std::swap(grid, scratch.spare);
  }
  if (changed.empty()) return;
  const CellRect columns_changed{changed.x0 - columns.x0, changed.x1 - columns.x0, changed.y0 - columns.y0,
                                 changed.y1 - columns.y0};
  const CellRect target = grown(columns_changed, margin, grid.grid);
  if (!target.empty()) compute_cells(grid, columns, settings, target, scratch);
}

}  // namespace sarmap::topo
