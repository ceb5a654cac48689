// mark_ray_cells() and mark_ray_cells_dense() written once over the xsimd
// architecture, compiled per instruction set by ray_marking_{avx2,avx512}.cpp.
// Each lane of a vector of floats (16 on AVX-512, 8 on AVX2) carries one
// ray's DdaState (dda_walk.hpp) and steps it to the same values as
// dda_step() (the same float operations on the same operands), so every
// lane visits exactly the cells the scalar walk visits. Three fields are
// held one step ahead, which takes work off the chain that runs from one
// step to the next (the walk waits on that chain, not on its arithmetic):
// the face plus the step, the cell before the last, and the next crossing
// already +inf where it would lead past the last cell (RayStage,
// ray_stage.hpp, which also sets the rays up).
// Cells are held as floats too (integers below 2^24 are exact in a float).
// A lane whose ray reaches its end cell takes the next ray, set up ahead in
// a RayStage, at the next refill (one every kStepsPerRefill steps).
// walk_ray_lanes() does that and hands each step's cells to a marker, which
// finds the word and bit of each lane's cell in vector code and ORs them in
// scalar code one step later: a scalar load right after the vector store
// of the same step waited for the store to commit (store forwarding does
// not split a vector store), which cost more than the step itself. Two
// markers: BlockSinkMarker asks a sink for a lane's block when the lane
// enters a new one (one step in eight or so); DenseGridMarker computes the
// word in a dense grid of blocks and needs no look-up at all.
#pragma once

// GCC 12's AVX-512 intrinsics make their "undefined" vectors from
// themselves (`__m512 __Y = __Y;`), which -Wuninitialized reports wherever
// it inlines them into a function it emits on its own (the markers'
// record() in the sanitizer build); GCC 13 silences it in the header.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <xsimd/xsimd.hpp>
#pragma GCC diagnostic pop
#else
#include <xsimd/xsimd.hpp>
#endif

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "kernels/dda_walk.hpp"
#include "kernels/ray_marking.hpp"
#include "kernels/ray_stage.hpp"

namespace sarmap::kernels {
namespace {

template <class Arch>
inline unsigned lane_bits(const xsimd::batch_bool<float, Arch>& b) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    return static_cast<unsigned>(static_cast<__mmask16>(b));
  } else
#endif
  {
    static_assert(std::is_base_of_v<xsimd::avx, Arch>, "lane_bits: no mask extraction for this instruction set");
    return static_cast<unsigned>(_mm256_movemask_ps(b));
  }
}

// Steps between two refills of the lanes whose rays arrived. Refilled at
// once, the lanes took a branch on arrival about every fifth step, taken
// at random and mispredicted; a lane now idles for up to this many steps
// after its ray arrives, a few percent of the lane steps against a
// mispredicted branch every few steps (the A/B is in docs/perf-history.md).
inline constexpr int kStepsPerRefill = 8;

// Walks the rays of a RayStage(stage_args...) from its start, N at a time, calling
// marker.record(cells, active, buffer) with each step's cells (3 vectors,
// one per axis, lanes not in active hold nothing to mark) and then
// marker.mark(other buffer) to mark the step before. Returns the cells visited.
template <class Arch, class Marker, class... StageArgs>
std::size_t walk_ray_lanes(Marker& marker, const StageArgs&... stage_args) {
  using D = xsimd::batch<float, Arch>;
  constexpr std::size_t N = D::size;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  static_assert(N <= 16, "lane sets are bits of an unsigned");

  // The lanes' states in registers, field by field in RayStage's order, all
  // parked to begin with. The start relative to its cell is the same for
  // every ray (dda_setup() computes it from the start alone).
  using Stage = RayStage<N>;
  D state[Stage::kFields];
#pragma GCC unroll 21
  for (int f = 0; f < Stage::kFields; ++f) state[f] = D(Stage::parked(f));
  D* const vv = state + Stage::kV;
  D* const before_lastv = state + Stage::kBeforeLast;
  D* const stepv = state + Stage::kStep;
  D* const next_facev = state + Stage::kNextFace;
  D* const invv = state + Stage::kInv;
  D* const tv = state + Stage::kT;
  D* const nextv = state + Stage::kNext;
  // A local, not a parameter: the compiler then knows the marker's stores
  // do not change it.
  Stage stage(stage_args...);
  const DdaState& at_start = stage.at_start();
  const D startv[3] = {D(at_start.start[0]), D(at_start.start[1]), D(at_start.start[2])};
  const D inf(kInf), tie(kDdaTieParameter);
  unsigned active = 0;
  std::size_t visits = 0, parity = 0;

  // Gives the lanes in `lanes` the next staged rays, and parks those left
  // without one.
  const auto refill = [&](unsigned lanes) {
    const std::size_t ready = stage.ready(static_cast<std::size_t>(std::popcount(lanes)));
    unsigned fill = lanes;  // the lowest `ready` of them
    while (static_cast<std::size_t>(std::popcount(fill)) > ready) fill &= ~(1u << (31 - std::countl_zero(fill)));
#if defined(__AVX512F__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
      // Straight into the registers: an expanding load per field puts the
      // next rays into the masked lanes, in order. With 16 lanes a lane
      // changes ray every few steps, and the trip of the whole state through
      // memory that AVX2 takes below made the walk measurably slower
      // (docs/perf-history.md).
      const auto m = static_cast<__mmask16>(fill), park = static_cast<__mmask16>(lanes & ~fill);
#pragma GCC unroll 21
      for (int f = 0; f < Stage::kFields; ++f) {
        state[f] = D(_mm512_mask_expandloadu_ps(state[f], m, stage.field(f)));
        if (park != 0) state[f] = D(_mm512_mask_mov_ps(state[f], park, _mm512_set1_ps(Stage::parked(f))));
      }
    } else
#endif
    {
      // Through memory: AVX2 has no expanding load.
      alignas(64) float lane_values[Stage::kFields][N];
#pragma GCC unroll 21
      for (int f = 0; f < Stage::kFields; ++f) state[f].store_aligned(lane_values[f]);
      std::size_t taken = 0;
      for (unsigned bits = lanes; bits != 0; bits &= bits - 1) {
        const auto lane = static_cast<std::size_t>(std::countr_zero(bits));
        const bool parks = ((fill >> lane) & 1u) == 0;
        for (int f = 0; f < Stage::kFields; ++f) lane_values[f][lane] = parks ? Stage::parked(f) : stage.field(f)[taken];
        taken += parks ? 0 : 1;
      }
#pragma GCC unroll 21
      for (int f = 0; f < Stage::kFields; ++f) state[f] = D::load_aligned(lane_values[f]);
    }
    stage.take(static_cast<std::size_t>(std::popcount(fill)));
    active = (active & ~lanes) | fill;
  };
  constexpr unsigned kAllLanes = N == 16 ? 0xffffu : (1u << N) - 1u;
  refill(kAllLanes);
  if (active == 0) return 0;

  D tmin = xsimd::min(xsimd::min(tv[0], tv[1]), tv[2]);
  while (true) {
    // kStepsPerRefill steps without a branch on the data: a lane whose ray
    // arrives leaves `active` and idles until the refill below.
#pragma GCC unroll 1
    for (int k = 0; k < kStepsPerRefill; ++k) {
      marker.record(vv, active, parity);
      marker.mark(parity ^ 1);
      visits += static_cast<std::size_t>(std::popcount(active));
      parity ^= 1;

      // dda_step() on every lane. An axis that steps takes next as it is
      // (+inf once on its last cell, decided off the chain below), and the
      // minimum of the crossings is taken once per step, for the next step
      // and the arrival test alike. Idle lanes step too, harmlessly: they
      // mark nothing and are overwritten when refilled.
      for (int i = 0; i < 3; ++i) {
        const auto stepping = (tv[i] - tie) <= tmin;
        vv[i] = xsimd::select(stepping, vv[i] + stepv[i], vv[i]);
        next_facev[i] = xsimd::select(stepping, next_facev[i] + stepv[i], next_facev[i]);
        tv[i] = xsimd::select(stepping, nextv[i], tv[i]);
        nextv[i] = xsimd::select(vv[i] == before_lastv[i], inf, (next_facev[i] - startv[i]) * invv[i]);
      }
      tmin = xsimd::min(xsimd::min(tv[0], tv[1]), tv[2]);
      // A lane has arrived when every axis is done (t = +inf on each), which
      // is exactly when its cell is the end cell: an axis's t becomes +inf
      // only as it steps onto its last cell, or from the start when it never moves.
      active &= ~lane_bits<Arch>(tmin == inf);
    }
    const unsigned idle = kAllLanes & ~active;
    if (idle != 0) {
      refill(idle);
      if (active == 0) break;
      tmin = xsimd::min(xsimd::min(tv[0], tv[1]), tv[2]);
    }
  }
  marker.mark(parity ^ 1);  // the last step's marks (the loop left before marking them)
  return visits;
}

// Marks into block masks found through a sink (BlockMaskSink).
template <class Arch>
class BlockSinkMarker {
 public:
  using D = xsimd::batch<float, Arch>;
  static constexpr std::size_t N = D::size;

  explicit BlockSinkMarker(const BlockMaskSink& sink) : sink_(sink) {
    for (int i = 0; i < 3; ++i) block_[i] = D(std::numeric_limits<float>::quiet_NaN());
  }

  void record(const D* cell, unsigned active, std::size_t buffer) {
    // Cell coordinates are integers below 2^24 in floats, so the block
    // (floor of a division by 8) and the place in it are exact.
    D b[3], in_block[3];
    for (int i = 0; i < 3; ++i) {
      b[i] = xsimd::floor(cell[i] * D(0.125f));
      in_block[i] = cell[i] - b[i] * D(8.0f);
    }
    (in_block[0] + in_block[1] * D(8.0f) + in_block[2] * D(64.0f)).store_aligned(local_[buffer]);
    // Written as "not equal" by hand: a NaN (no block yet) must count as a
    // change, and xsimd's != is an ordered compare, false for NaN.
    moved_[buffer] = ~lane_bits<Arch>((b[0] == block_[0]) && (b[1] == block_[1]) && (b[2] == block_[2])) & active;
    marking_[buffer] = active;
    if (moved_[buffer] != 0) {
      for (int i = 0; i < 3; ++i) {
        b[i].store_aligned(new_block_[buffer][i]);
        block_[i] = b[i];  // lanes that did not move already hold b
      }
    }
  }

  void mark(std::size_t buffer) {
    for (unsigned bits = moved_[buffer]; bits != 0; bits &= bits - 1) {
      const int lane = std::countr_zero(bits);
      block_index_[lane] = sink_.block_index(sink_.context, static_cast<std::int32_t>(new_block_[buffer][0][lane]),
                                             static_cast<std::int32_t>(new_block_[buffer][1][lane]),
                                             static_cast<std::int32_t>(new_block_[buffer][2][lane]));
    }
    std::uint64_t* const masks = *sink_.masks;
    // Every lane, without branches (nearly all are marking): a lane that is
    // not ORs nothing into its last word.
    const unsigned lanes = marking_[buffer];
    if (lanes == 0) return;  // the first step: no marks and maybe no masks yet
#pragma GCC unroll 16
    for (std::size_t lane = 0; lane < N; ++lane) {
      const auto cell = static_cast<unsigned>(local_[buffer][lane]);
      const std::uint64_t bit = static_cast<std::uint64_t>((lanes >> lane) & 1u) << (cell & 63);
      masks[kMarkBlockWords * block_index_[lane] + (cell >> 6)] |= bit;
    }
  }

 private:
  const BlockMaskSink& sink_;
  D block_[3];  // the block each lane marks into (NaN: none yet)
  // Per step, double-buffered: each lane's cell index in its block, the
  // blocks of lanes that entered one, which lanes moved, which marked.
  alignas(64) float local_[2][N];
  alignas(64) float new_block_[2][3][N];
  unsigned moved_[2] = {0, 0}, marking_[2] = {0, 0};
  std::uint32_t block_index_[N] = {};
};

// Marks into a DenseMaskGrid: word = 8 x the block's place in the grid + z
// in the block, bit = x + 8 y in the block. The block and the place in it
// are found in floats (exact, as above); the word in 32-bit integers, which
// hold any word of a grid (fewer than 2^31) where a float would not.
template <class Arch>
class DenseGridMarker {
 public:
  using D = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  static constexpr std::size_t N = D::size;

  explicit DenseGridMarker(const DenseMaskGrid& grid)
      : words_(grid.words),
        first_{I(grid.first_block[0]), I(grid.first_block[1]), I(grid.first_block[2])},
        blocks_x_(grid.blocks[0]),
        blocks_y_(grid.blocks[1]) {}

  void record(const D* cell, unsigned active, std::size_t buffer) {
    D b[3], in_block[3];
    for (int i = 0; i < 3; ++i) {
      b[i] = xsimd::floor(cell[i] * D(0.125f));
      in_block[i] = cell[i] - b[i] * D(8.0f);
    }
    // Lanes not marking may be anywhere (a parked lane sits on cell 0): mark()
    // sends them to word 0 with no bit, so their word need not be in the grid
    // (the integer arithmetic wraps harmlessly for them).
    const I block = ((xsimd::to_int(b[2]) - first_[2]) * blocks_y_ + (xsimd::to_int(b[1]) - first_[1])) * blocks_x_ +
                    (xsimd::to_int(b[0]) - first_[0]);
    ((block << 3) + xsimd::to_int(in_block[2])).store_aligned(word_[buffer]);
    xsimd::to_int(in_block[0] + in_block[1] * D(8.0f)).store_aligned(bit_[buffer]);
    marking_[buffer] = active;
  }

  void mark(std::size_t buffer) {
    const unsigned lanes = marking_[buffer];
#pragma GCC unroll 16
    for (std::size_t lane = 0; lane < N; ++lane) {
      const std::uint32_t on = (lanes >> lane) & 1u;
      const std::uint64_t bit = static_cast<std::uint64_t>(on) << bit_[buffer][lane];
      words_[static_cast<std::uint32_t>(word_[buffer][lane]) & (0u - on)] |= bit;
    }
  }

 private:
  std::uint64_t* words_;
  I first_[3], blocks_x_, blocks_y_;
  // Per step, double-buffered: each lane's word and bit, which lanes mark.
  alignas(64) std::int32_t word_[2][N] = {};
  alignas(64) std::int32_t bit_[2][N] = {};
  unsigned marking_[2] = {0, 0};
};

template <class Arch>
std::size_t mark_ray_cells_impl(const double start[3], const double* ends, std::size_t count,
                                const BlockMaskSink& sink) {
  BlockSinkMarker<Arch> marker(sink);
  return walk_ray_lanes<Arch>(marker, start, ends, count);
}

template <class Arch>
std::size_t mark_ray_cells_dense_impl(const double start[3], const double* ends, std::size_t count,
                                      const DenseMaskGrid& grid) {
  DenseGridMarker<Arch> marker(grid);
  return walk_ray_lanes<Arch>(marker, start, ends, count);
}

template <class Arch>
std::size_t mark_ray_pieces_dense_impl(const double start[3], const RayPieces& pieces,
                                       const DenseMaskGrid& grid) {
  DenseGridMarker<Arch> marker(grid);
  return walk_ray_lanes<Arch>(marker, start, pieces);
}

}  // namespace
}  // namespace sarmap::kernels
