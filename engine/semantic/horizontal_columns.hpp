// Columns of a horizontal grid, each packed into one word, for the rules
// that group points by where they stand on the floor plan (ramp side
// faces, wall bands, wall feet).
#pragma once

#include <cmath>
#include <cstdint>

namespace sarmap::horizontal_columns {

// Points farther out than this (metres) get no column: their indices would
// not fit the packed key (the metric map rejects them anyway).
inline constexpr double kMaxHorizontal = 1.0e6;
inline constexpr std::int64_t kOffset = std::int64_t{1} << 31;

inline bool in_reach(double x, double y) { return std::abs(x) <= kMaxHorizontal && std::abs(y) <= kMaxHorizontal; }

// Two 32-bit column indices in one word.
inline std::uint64_t key(std::int64_t cx, std::int64_t cy) {
  return (static_cast<std::uint64_t>(cx + kOffset) << 32) | static_cast<std::uint64_t>(cy + kOffset);
}
inline std::int64_t key_x(std::uint64_t key) { return static_cast<std::int64_t>(key >> 32) - kOffset; }
inline std::int64_t key_y(std::uint64_t key) { return static_cast<std::int64_t>(key & 0xffffffffu) - kOffset; }

// The column index of a coordinate, for columns 1 / inverse_size wide.
inline std::int64_t index(double coordinate, double inverse_size) {
  return static_cast<std::int64_t>(std::floor(coordinate * inverse_size));
}
// The key of the column holding (x, y); only for points in_reach.
inline std::uint64_t key_of(double x, double y, double inverse_size) {
  return key(index(x, inverse_size), index(y, inverse_size));
}

}  // namespace sarmap::horizontal_columns
