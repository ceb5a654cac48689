#include "engine/topo/planning_grid.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "engine/core/error.hpp"
#include "engine/core/vector_headroom.hpp"

namespace sarmap::topo {

namespace {

void check_shape(int width, int height, double resolution, const Eigen::Vector2d& origin) {
  if (width <= 0 || height <= 0 ||
      static_cast<std::int64_t>(width) * height > std::numeric_limits<std::int32_t>::max()) {
    throw Error(ErrorCode::InvalidArgument, "topo: a planning grid of " + std::to_string(width) + " x " +
                                                std::to_string(height) +
                                                " cells (both must be positive, the product below 2^31)");
  }
  if (!std::isfinite(resolution) || resolution <= 0.0) {
    throw Error(ErrorCode::InvalidArgument,
                "topo: the planning grid's resolution must be a finite number > 0, not " +
                    std::to_string(resolution));
  }
  if (!origin.allFinite())
    throw Error(ErrorCode::InvalidArgument, "topo: the planning grid's origin is not finite");
}

}  // namespace

PlanningGrid::PlanningGrid(int width, int height, double resolution, const Eigen::Vector2d& origin,
                           CellState fill)
    : width_(width), height_(height), resolution_(resolution), origin_(origin) {
  check_shape(width, height, resolution, origin);
  cells_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), fill);
}

void PlanningGrid::reset(int width, int height, double resolution, const Eigen::Vector2d& origin, CellState fill) {
  check_shape(width, height, resolution, origin);
  width_ = width;
  height_ = height;
  resolution_ = resolution;
  origin_ = origin;
  assign_with_headroom(cells_, static_cast<std::size_t>(width) * static_cast<std::size_t>(height), fill);
}

GridCell PlanningGrid::cell_at(const Eigen::Vector2d& world) const {
  const Eigen::Vector2d local = (world - origin_) / resolution_;
  // Clamped before the cast: a point far outside must give a cell outside,
  // not an overflowed int that happens to land inside.
  const auto to_int = [](double v) {
    const double limit = static_cast<double>(std::numeric_limits<int>::max());
    if (!(v > -limit)) return std::numeric_limits<int>::min();
    if (!(v < limit)) return std::numeric_limits<int>::max();
    return static_cast<int>(std::floor(v));
  };
  return {to_int(local.x()), to_int(local.y())};
}

Eigen::Vector2d PlanningGrid::centre_of(GridCell cell) const {
  return origin_ + resolution_ * Eigen::Vector2d(cell.x + 0.5, cell.y + 0.5);
}

}  // namespace sarmap::topo
