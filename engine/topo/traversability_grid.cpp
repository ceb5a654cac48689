#include "engine/topo/traversability_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace sarmap::topo {
namespace {

bool walkable(ClassId label) {
  return label == ClassId::Terrain || label == ClassId::InclinedRamp || label == ClassId::FlatRamp;
}

}  // namespace

TraversabilityGrid traversability_grid(const VoxelColumns& columns, const TopoSettings& settings) {
  validate(settings);
  const double res = columns.resolution;
  TraversabilityGrid out;
  if (columns.empty()) {
    out.grid = PlanningGrid(1, 1, res, Eigen::Vector2d::Zero());
    out.ground.assign(1, std::nanf(""));
    out.ground_class.assign(1, ClassId::Unknown);
    out.near_drop.assign(1, 0);
    return out;
  }
  const int width = columns.width, height = columns.height;
  out.grid = PlanningGrid(width, height, res, Eigen::Vector2d(columns.x0 * res, columns.y0 * res), CellState::Unknown);
  out.ground.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), std::nanf(""));
  out.ground_class.assign(out.ground.size(), ClassId::Unknown);
  // The robot's height in voxels: an occupied voxel closer above a surface
  // than this leaves no room to drive there.
  const auto clearance = static_cast<std::int32_t>(std::ceil(settings.robot_height / res));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t c = columns.column(x, y);
      const std::uint32_t begin = columns.start[c], end = columns.start[c + 1];
      if (begin == end) continue;
      const GridCell cell{x, y};
      CellState state = CellState::Occupied;
      for (std::uint32_t i = end; i-- > begin;) {
        if (!walkable(columns.label[i])) continue;
        if (i + 1 == end || columns.z[i + 1] - columns.z[i] > clearance) {
          out.ground[out.grid.index_of(cell)] = static_cast<float>((columns.z[i] + 0.5) * res);
          out.ground_class[out.grid.index_of(cell)] = columns.label[i];
          state = CellState::Free;
          break;
        }
      }
      out.grid.set(cell, state);
    }
  }

  // Pinholes and cracks: a cell nobody's ray ended in, between seen ground
  // on two opposite sides at heights within a step, is that ground (a
  // sensor's pixel grid leaves such one-cell gaps, lines of them across a
  // slope). One pass over the cells as they were, so gaps never grow.
  const std::vector<CellState> seen(out.grid.cells().begin(), out.grid.cells().end());
  for (int y = 1; y + 1 < height; ++y) {
    for (int x = 1; x + 1 < width; ++x) {
      const std::size_t i = out.grid.index_of({x, y});
      if (seen[i] != CellState::Unknown) continue;
      for (const auto& [a, b] : {std::pair{GridCell{x - 1, y}, GridCell{x + 1, y}},
                                 std::pair{GridCell{x, y - 1}, GridCell{x, y + 1}}}) {
        const std::size_t ia = out.grid.index_of(a), ib = out.grid.index_of(b);
        if (seen[ia] != CellState::Free || seen[ib] != CellState::Free) continue;
        if (std::abs(out.ground[ia] - out.ground[ib]) > settings.max_step) continue;
        out.grid.set({x, y}, CellState::Free);
        out.ground[i] = (out.ground[ia] + out.ground[ib]) / 2;
        out.ground_class[i] = out.ground_class[ia];
        break;
      }
    }
  }

  // Drops: a free cell more than a step above a free neighbour is a rim.
  std::vector<std::uint8_t> blocked(out.ground.size(), 0), rim(out.ground.size(), 0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t i = out.grid.index_of({x, y});
      if (out.grid.cells()[i] == CellState::Occupied) {
        blocked[i] = 1;
        continue;
      }
      if (out.grid.cells()[i] != CellState::Free) continue;
      for (int dy = -1; dy <= 1 && !rim[i]; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const GridCell n{x + dx, y + dy};
          if (!out.grid.contains(n) || out.grid.at(n) != CellState::Free) continue;
          if (out.ground[i] - out.ground[out.grid.index_of(n)] > settings.max_step) {
            blocked[i] = rim[i] = 1;
            break;
          }
        }
      }
    }
  }
  // Blocked cells grow by the robot's radius (cell centres within it).
  const int reach = static_cast<int>(std::floor(settings.robot_radius / res + 1e-9));
  std::vector<std::pair<int, int>> disk;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      if ((dx * dx + dy * dy) * res * res <= settings.robot_radius * settings.robot_radius + 1e-12) disk.emplace_back(dx, dy);
    }
  }
  out.near_drop.assign(out.ground.size(), 0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t i = out.grid.index_of({x, y});
      if (!blocked[i]) continue;
      for (const auto& [dx, dy] : disk) {
        const GridCell n{x + dx, y + dy};
        if (!out.grid.contains(n)) continue;
        out.grid.set(n, CellState::Occupied);
        if (rim[i]) out.near_drop[out.grid.index_of(n)] = 1;
      }
    }
  }
  return out;
}

}  // namespace sarmap::topo
