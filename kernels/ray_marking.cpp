#include "kernels/ray_marking.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kernels/dda_walk.hpp"

namespace sarmap::kernels {

std::size_t mark_ray_cells_reference(const double start[3], const double* ends, std::size_t count,
                                     const BlockMaskSink& sink) {
  std::size_t visits = 0;
  // A ray stays in one block for several cells: ask the sink only on a change
  // (indices are stable; only the mask array may move, so it is re-read).
  std::int32_t cached[3] = {0, 0, 0};
  std::uint32_t b = 0;
  bool have_block = false;
  for (std::size_t r = 0; r < count; ++r) {
    visits += dda_walk(start, ends + 3 * r, [&](std::int32_t x, std::int32_t y, std::int32_t z) {
      const std::int32_t bx = x >> kMarkBlockShift, by = y >> kMarkBlockShift, bz = z >> kMarkBlockShift;
      if (!have_block || bx != cached[0] || by != cached[1] || bz != cached[2]) {
        b = sink.block_index(sink.context, bx, by, bz);
        cached[0] = bx, cached[1] = by, cached[2] = bz;
        have_block = true;
      }
      const int local = (x & 7) | ((y & 7) << 3) | ((z & 7) << 6);
      (*sink.masks)[kMarkBlockWords * b + static_cast<std::size_t>(local >> 6)] |= std::uint64_t{1} << (local & 63);
      return true;
    });
  }
  return visits;
}

std::size_t mark_ray_cells(const double start[3], const double* ends, std::size_t count, const BlockMaskSink& sink,
                           SimdLevel level) {
  if (!simd_level_supported(level)) throw std::invalid_argument("mark_ray_cells: instruction set not supported");
  switch (level) {
    case SimdLevel::Avx512: return detail::mark_ray_cells_avx512(start, ends, count, sink);
    case SimdLevel::Avx2: return detail::mark_ray_cells_avx2(start, ends, count, sink);
    case SimdLevel::Sse42: break;  // two lanes of doubles do not pay for the lane bookkeeping
  }
  return mark_ray_cells_reference(start, ends, count, sink);
}

DenseMaskGrid dense_grid_covering(const double start[3], const double* ends, std::size_t count) {
  double lo[3] = {start[0], start[1], start[2]}, hi[3] = {start[0], start[1], start[2]};
  for (std::size_t r = 0; r < count; ++r) {
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], ends[3 * r + i]), hi[i] = std::max(hi[i], ends[3 * r + i]);
  }
  DenseMaskGrid grid{};
  for (int i = 0; i < 3; ++i) {
    // A cell is floor(coordinate), as in dda_setup().
    grid.first_block[i] = static_cast<std::int32_t>(std::floor(lo[i])) >> kMarkBlockShift;
    grid.blocks[i] = (static_cast<std::int32_t>(std::floor(hi[i])) >> kMarkBlockShift) - grid.first_block[i] + 1;
  }
  return grid;
}

std::size_t dense_grid_blocks(const DenseMaskGrid& grid) {
  return static_cast<std::size_t>(grid.blocks[0]) * static_cast<std::size_t>(grid.blocks[1]) *
         static_cast<std::size_t>(grid.blocks[2]);
}

std::size_t mark_ray_cells_dense_reference(const double start[3], const double* ends, std::size_t count,
                                           const DenseMaskGrid& grid) {
  std::size_t visits = 0;
  for (std::size_t r = 0; r < count; ++r) {
    visits += dda_walk(start, ends + 3 * r, [&](std::int32_t x, std::int32_t y, std::int32_t z) {
      const std::int64_t i = (x >> kMarkBlockShift) - grid.first_block[0];
      const std::int64_t j = (y >> kMarkBlockShift) - grid.first_block[1];
      const std::int64_t k = (z >> kMarkBlockShift) - grid.first_block[2];
      const std::int64_t block = i + grid.blocks[0] * (j + std::int64_t{grid.blocks[1]} * k);
      grid.words[kMarkBlockWords * static_cast<std::size_t>(block) + static_cast<std::size_t>(z & 7)] |=
          std::uint64_t{1} << ((x & 7) | ((y & 7) << 3));
      return true;
    });
  }
  return visits;
}

std::size_t mark_ray_cells_dense(const double start[3], const double* ends, std::size_t count,
                                 const DenseMaskGrid& grid, SimdLevel level) {
  if (!simd_level_supported(level)) throw std::invalid_argument("mark_ray_cells_dense: instruction set not supported");
  switch (level) {
    case SimdLevel::Avx512: return detail::mark_ray_cells_dense_avx512(start, ends, count, grid);
    case SimdLevel::Avx2: return detail::mark_ray_cells_dense_avx2(start, ends, count, grid);
    case SimdLevel::Sse42: break;  // as in mark_ray_cells
  }
  return mark_ray_cells_dense_reference(start, ends, count, grid);
}

std::size_t mark_ray_pieces_dense(const double start[3], const RayPieces& pieces, const DenseMaskGrid& grid,
                                  SimdLevel level) {
  if (!simd_level_supported(level)) {
    throw std::invalid_argument("mark_ray_pieces_dense: instruction set not supported");
  }
  switch (level) {
    case SimdLevel::Avx512: return detail::mark_ray_pieces_dense_avx512(start, pieces, grid);
    case SimdLevel::Avx2: return detail::mark_ray_pieces_dense_avx2(start, pieces, grid);
    case SimdLevel::Sse42: break;  // as in mark_ray_cells
  }
  std::size_t visits = 0;
  const double* ends = nullptr;
  for (std::size_t count = 0; pieces.next(pieces.context, &ends, &count);) {
    visits += mark_ray_cells_dense_reference(start, ends, count, grid);
  }
  return visits;
}

}  // namespace sarmap::kernels
