// A 2-D traversability grid for planning (free / occupied / unknown cells) in
// the plane, with world <-> cell conversion. Row-major, row 0 at the lowest y,
// as a map is drawn in world coordinates (ROS map files flip it when written).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "engine/core/capacity_bytes.hpp"

namespace sarmap::topo {

enum class CellState : std::uint8_t { Free = 0, Occupied = 1, Unknown = 2 };

struct GridCell {
  int x = 0;  // column, growing with world x
  int y = 0;  // row, growing with world y
  friend bool operator==(const GridCell&, const GridCell&) = default;
};

class PlanningGrid {
 public:
  PlanningGrid() = default;
  // origin: world (x, y) of cell (0, 0)'s lower-left corner. Throws
  // sarmap::Error (InvalidArgument) unless width and height are positive
  // with a product below 2^31, and resolution and origin are finite
  // (resolution > 0).
  PlanningGrid(int width, int height, double resolution, const Eigen::Vector2d& origin,
               CellState fill = CellState::Unknown);
  // The same on this grid's storage, reallocated (with half again as much
  // room) only when it is too small: for a grid that grows with a map.
  void reset(int width, int height, double resolution, const Eigen::Vector2d& origin,
             CellState fill = CellState::Unknown);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution() const { return resolution_; }
  const Eigen::Vector2d& origin() const { return origin_; }

  bool contains(GridCell cell) const {
    return cell.x >= 0 && cell.y >= 0 && cell.x < width_ && cell.y < height_;
  }
  // Unchecked: the caller knows the cell is inside (see contains).
  std::size_t index_of(GridCell cell) const {
    return static_cast<std::size_t>(cell.y) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(cell.x);
  }
  CellState at(GridCell cell) const { return cells_[index_of(cell)]; }
  void set(GridCell cell, CellState state) { cells_[index_of(cell)] = state; }
  std::span<const CellState> cells() const { return cells_; }
  std::span<CellState> cells() { return cells_; }
  // Bytes held, by capacity (reset() keeps room beyond the cells).
  std::size_t memory_bytes() const { return capacity_bytes(cells_); }

  // The cell whose square holds the point (lower and left edges belong to
  // the cell). May lie outside the grid: check with contains().
  GridCell cell_at(const Eigen::Vector2d& world) const;
  Eigen::Vector2d centre_of(GridCell cell) const;

 private:
  int width_ = 0;
  int height_ = 0;
  double resolution_ = 1.0;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  std::vector<CellState> cells_;
};

}  // namespace sarmap::topo
