// Marks every cell that rays from one start point pass through (dda_walk.hpp's
// exact DDA, end cells excluded) as a bit in 8 x 8 x 8-cell block masks: the
// free-space pass of ray integration. The vector versions walk one ray per
// SIMD lane (16 floats on AVX-512, 8 on AVX2), so the DDA's serial
// min-compare-select chain is paid once per step of 16 rays instead of once
// per cell; the bits are the same as walking each ray alone.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/simd_level.hpp"

namespace sarmap::kernels {

inline constexpr int kMarkBlockShift = 3;                     // blocks of 8 cells per axis
inline constexpr std::size_t kMarkBlockWords = 512 / 64;     // one bit per cell of a block

// Where the bits go. block_index(context, bx, by, bz) returns the index of the
// block at block coordinates (cell >> 3 per axis), creating it if needed;
// its 8 mask words are (*masks)[8 * index .. 8 * index + 7]. block_index may
// move the mask array (it grows), so *masks is re-read after every call.
struct BlockMaskSink {
  std::uint32_t (*block_index)(void* context, std::int32_t bx, std::int32_t by, std::int32_t bz);
  void* context;
  std::uint64_t* const* masks;
};

// Walks the rays from start to ends[3 * r .. 3 * r + 2] for r < count (cell
// units, all finite, cells within +-2^24: the vector walks hold cells in
// floats; the map's keys are below 2^20) and sets the bit of every cell
// visited. Returns the number of cells visited (repeats included). The order
// in which cells are marked differs between levels; the bits set do not.
std::size_t mark_ray_cells(const double start[3], const double* ends, std::size_t count, const BlockMaskSink& sink,
                           SimdLevel level);

// One ray at a time with dda_walk(): the reference, and the SSE4.2 path.
std::size_t mark_ray_cells_reference(const double start[3], const double* ends, std::size_t count,
                                     const BlockMaskSink& sink);

// Where the bits go when the rays' box of blocks is known and small: a dense
// grid of blocks, block (first_block + (i, j, k)) owning the 8 words from
// words[8 * (i + blocks[0] * (j + blocks[1] * k))]. Within a block the word is
// the cell's z and the bit x + 8 y, the same layout as the sink's masks. No
// look-up per block, which makes it much faster (docs/perf-history.md); the grid
// must hold every cell of the walks (the blocks of start and of every end)
// and have fewer than 2^31 words.
struct DenseMaskGrid {
  std::int32_t first_block[3];
  std::int32_t blocks[3];
  std::uint64_t* words;
};

// The smallest grid (words left null) that holds every cell of the walks
// from start to ends[3 r ..], r < count: the box of the blocks of start and
// of every end (a walk's cells lie between its first and last cell on every
// axis). Coordinates in cell units, finite and within int32 range.
DenseMaskGrid dense_grid_covering(const double start[3], const double* ends, std::size_t count);
// Blocks in a grid; its words are kMarkBlockWords times as many.
std::size_t dense_grid_blocks(const DenseMaskGrid& grid);

// mark_ray_cells() into a dense grid.
std::size_t mark_ray_cells_dense(const double start[3], const double* ends, std::size_t count,
                                 const DenseMaskGrid& grid, SimdLevel level);
// One ray at a time with dda_walk(): the reference, and the SSE4.2 path.
std::size_t mark_ray_cells_dense_reference(const double start[3], const double* ends, std::size_t count,
                                           const DenseMaskGrid& grid);

// Rays handed to a walk a piece at a time: next(context, &ends, &count)
// gives the next piece (ends[3 r ..], r < count; it may be empty) and
// returns false when there is none, which ends the walk once the rays taken
// so far are walked. The rays of a piece stay put until the walk returns.
struct RayPieces {
  bool (*next)(void* context, const double** ends, std::size_t* count);
  void* context;
};

// mark_ray_cells_dense() over every piece of pieces, as if their rays were
// one array: the vector walks ask for the next piece while the lanes are
// still walking the last one's rays, so lanes do not drain (sit idle while
// the longest rays of a call finish) between pieces, only at the end. For
// rays that become known a piece at a time (ScanRays's walk beside the merge).
std::size_t mark_ray_pieces_dense(const double start[3], const RayPieces& pieces, const DenseMaskGrid& grid,
                                  SimdLevel level);

namespace detail {
std::size_t mark_ray_cells_avx2(const double start[3], const double* ends, std::size_t count,
                                const BlockMaskSink& sink);
std::size_t mark_ray_cells_avx512(const double start[3], const double* ends, std::size_t count,
                                  const BlockMaskSink& sink);
std::size_t mark_ray_cells_dense_avx2(const double start[3], const double* ends, std::size_t count,
                                      const DenseMaskGrid& grid);
std::size_t mark_ray_cells_dense_avx512(const double start[3], const double* ends, std::size_t count,
                                        const DenseMaskGrid& grid);
std::size_t mark_ray_pieces_dense_avx2(const double start[3], const RayPieces& pieces,
                                       const DenseMaskGrid& grid);
std::size_t mark_ray_pieces_dense_avx512(const double start[3], const RayPieces& pieces,
                                         const DenseMaskGrid& grid);
}  // namespace detail

}  // namespace sarmap::kernels
