// Packed keys of the grids the classifiers group points by, for hash maps
// keyed by place: the columns of a horizontal grid (the rules after the
// network, the geometric baseline's floor and caps) and the cells of a 3-D
// grid (the surface normals). One definition, so every grid packs alike.
#pragma once

#include <cmath>
#include <cstdint>

namespace sarmap::grid_keys {

// --- Columns: two 32-bit indices in one word ---

// Points farther out than this (metres) get no column: their indices would
// not fit the packed key (the metric map rejects them anyway).
inline constexpr double kMaxHorizontal = 1.0e6;
inline constexpr std::int64_t kColumnOffset = std::int64_t{1} << 31;

inline bool in_reach(double x, double y) {
  return std::abs(x) <= kMaxHorizontal && std::abs(y) <= kMaxHorizontal;
}

// The index of the column or cell holding a coordinate, for cells
// 1 / inverse_size wide.
inline std::int64_t index(double coordinate, double inverse_size) {
  return static_cast<std::int64_t>(std::floor(coordinate * inverse_size));
}

// Column (cx, cy); each index in [-2^31, 2^31).
inline std::uint64_t column_key(std::int64_t cx, std::int64_t cy) {
  return (static_cast<std::uint64_t>(cx + kColumnOffset) << 32) |
         static_cast<std::uint64_t>(cy + kColumnOffset);
}
inline std::int64_t column_x(std::uint64_t key) {
  return static_cast<std::int64_t>(key >> 32) - kColumnOffset;
}
inline std::int64_t column_y(std::uint64_t key) {
  return static_cast<std::int64_t>(key & 0xffffffffu) - kColumnOffset;
}
// The key of the column holding (x, y); only for points in_reach.
inline std::uint64_t column_key_of(double x, double y, double inverse_size) {
  return column_key(index(x, inverse_size), index(y, inverse_size));
}

// --- Cells: three 22-bit indices in one word ---

// Each index in [-2^21, 2^21): 2 x 10 km (the metric map's limits) at 1 cm.
inline constexpr std::int64_t kCellOffset = std::int64_t{1} << 21;

inline std::uint64_t cell_key(std::int64_t i, std::int64_t j, std::int64_t k) {
  return (static_cast<std::uint64_t>(i + kCellOffset) << 44) |
         (static_cast<std::uint64_t>(j + kCellOffset) << 22) | static_cast<std::uint64_t>(k + kCellOffset);
}

}  // namespace sarmap::grid_keys
