// mark_ray_cells() written once over the xsimd architecture, compiled per
// instruction set by ray_marking_{avx2,avx512}.cpp. Each lane of a vector of
// doubles carries one ray's DdaState (dda_walk.hpp) and steps it with the same
// operations as dda_step(), so every lane visits exactly the cells the scalar
// walk visits. A lane whose ray reaches its end cell takes the next ray.
// Per step the vector part also finds each lane's cell within its block and
// whether the lane entered a new block (one step in eight or so); only then
// does the lane ask the sink for the block. What is left scalar per cell is
// one OR into the lane's block mask.
#pragma once

#include <xsimd/xsimd.hpp>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "kernels/dda_walk.hpp"
#include "kernels/ray_marking.hpp"

namespace sarmap::kernels {
namespace {

template <class Arch>
inline unsigned lane_bits(const xsimd::batch_bool<double, Arch>& b) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    return static_cast<unsigned>(static_cast<__mmask8>(b));
  } else
#endif
  {
    static_assert(std::is_base_of_v<xsimd::avx, Arch>, "lane_bits: no mask extraction for this instruction set");
    return static_cast<unsigned>(_mm256_movemask_pd(b));
  }
}

template <class Arch>
std::size_t mark_ray_cells_impl(const double start[3], const double* ends, std::size_t count,
                                const BlockMaskSink& sink) {
  using D = xsimd::batch<double, Arch>;
  constexpr std::size_t N = D::size;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  static_assert(N <= 8, "lane sets are bits of an unsigned");

  // The lanes' states, by field and axis; the loop keeps them in registers
  // and goes through these arrays only when a lane changes ray.
  alignas(64) double v[3][N], last[3][N], step[3][N], face[3][N], inv[3][N], t[3][N], next[3][N], eps[N];
  alignas(64) double block[3][N];  // the block each lane marks into (NaN: none yet)
  // Per step, double-buffered (see the loop): each lane's cell index in its
  // block, the blocks of lanes that entered one, which lanes moved, marked.
  alignas(64) double local[2][N];
  alignas(64) double new_block[2][3][N];
  unsigned moved[2] = {0, 0}, marking[2] = {0, 0};
  std::size_t parity = 0;
  std::uint32_t block_index[N] = {};
  unsigned active = 0;
  std::size_t next_ray = 0, visits = 0;

  // Gives lane the next ray that visits anything, or parks it (no ray left):
  // a parked lane sits on its end cell with nothing to step.
  const auto load_lane = [&](std::size_t lane) {
    while (next_ray < count) {
      const DdaState s = dda_setup(start, ends + 3 * next_ray++);
      if (!s.moves) continue;
      for (int i = 0; i < 3; ++i) {
        v[i][lane] = s.v[i];
        last[i][lane] = s.last[i];
        step[i][lane] = s.step[i];
        face[i][lane] = s.face[i];
        inv[i][lane] = s.inv[i];
        t[i][lane] = s.t[i];
        next[i][lane] = s.next[i];
        block[i][lane] = kNaN;
      }
      eps[lane] = s.eps;
      active |= 1u << lane;
      return;
    }
    for (int i = 0; i < 3; ++i) {
      v[i][lane] = last[i][lane] = step[i][lane] = face[i][lane] = inv[i][lane] = next[i][lane] = 0.0;
      t[i][lane] = kInf;
      block[i][lane] = kNaN;
    }
    eps[lane] = 0.0;
    active &= ~(1u << lane);
  };
  for (std::size_t lane = 0; lane < N; ++lane) load_lane(lane);
  if (active == 0) return 0;

  D vv[3], lastv[3], stepv[3], facev[3], invv[3], tv[3], nextv[3], blockv[3], epsv;
  const auto load_state = [&] {
    for (int i = 0; i < 3; ++i) {
      vv[i] = D::load_aligned(v[i]);
      lastv[i] = D::load_aligned(last[i]);
      stepv[i] = D::load_aligned(step[i]);
      facev[i] = D::load_aligned(face[i]);
      invv[i] = D::load_aligned(inv[i]);
      tv[i] = D::load_aligned(t[i]);
      nextv[i] = D::load_aligned(next[i]);
      blockv[i] = D::load_aligned(block[i]);
    }
    epsv = D::load_aligned(eps);
  };
  const auto store_state = [&] {
    for (int i = 0; i < 3; ++i) {
      vv[i].store_aligned(v[i]);
      lastv[i].store_aligned(last[i]);
      stepv[i].store_aligned(step[i]);
      facev[i].store_aligned(face[i]);
      invv[i].store_aligned(inv[i]);
      tv[i].store_aligned(t[i]);
      nextv[i].store_aligned(next[i]);
      blockv[i].store_aligned(block[i]);
    }
    epsv.store_aligned(eps);
  };
  load_state();
  const D startv[3] = {D(start[0]), D(start[1]), D(start[2])};
  const D eighth(0.125), eight(8.0), sixty_four(64.0), inf(kInf);

  const auto mark_step = [&](std::size_t step_buffer) {
    for (unsigned bits = moved[step_buffer]; bits != 0; bits &= bits - 1) {
      const int lane = std::countr_zero(bits);
      block_index[lane] = sink.block_index(sink.context, static_cast<std::int32_t>(new_block[step_buffer][0][lane]),
                                           static_cast<std::int32_t>(new_block[step_buffer][1][lane]),
                                           static_cast<std::int32_t>(new_block[step_buffer][2][lane]));
    }
    std::uint64_t* const masks = *sink.masks;
    // Every lane, without branches (nearly all are marking): a lane that is
    // not ORs nothing into its last word.
    const unsigned marking_lanes = marking[step_buffer];
    if (marking_lanes == 0) return;  // the first step: no marks and maybe no masks yet
#pragma GCC unroll 8
    for (std::size_t lane = 0; lane < N; ++lane) {
      const auto cell = static_cast<unsigned>(local[step_buffer][lane]);
      const std::uint64_t bit = static_cast<std::uint64_t>((marking_lanes >> lane) & 1u) << (cell & 63);
      masks[kMarkBlockWords * block_index[lane] + (cell >> 6)] |= bit;
    }
  };
  while (true) {
    // Mark the lanes' current cells. Cell coordinates are integers in
    // doubles, so the block (floor of a division by 8) and the place in it
    // are exact. The lanes' values reach the scalar marking through memory,
    // one step late: a scalar load right after the vector store of the same
    // step waited for the store to commit (store forwarding does not split
    // a vector store), which cost more than the step itself.
    const std::size_t now = parity, before = parity ^ 1;
    D b[3], in_block[3];
    for (int i = 0; i < 3; ++i) {
      b[i] = xsimd::floor(vv[i] * eighth);
      in_block[i] = vv[i] - b[i] * eight;
    }
    (in_block[0] + in_block[1] * eight + in_block[2] * sixty_four).store_aligned(local[now]);
    // Written as "not equal" by hand: a NaN (no block yet) must count as a
    // change, and xsimd's != is an ordered compare, false for NaN.
    moved[now] = ~lane_bits<Arch>((b[0] == blockv[0]) && (b[1] == blockv[1]) && (b[2] == blockv[2])) & active;
    marking[now] = active;
    if (moved[now] != 0) {
      for (int i = 0; i < 3; ++i) {
        b[i].store_aligned(new_block[now][i]);
        blockv[i] = b[i];  // lanes that did not move already hold b
      }
    }
    mark_step(before);
    visits += static_cast<std::size_t>(std::popcount(active));
    parity = before;

    // dda_step() on every lane.
    const D tmin = xsimd::min(xsimd::min(tv[0], tv[1]), tv[2]);
    for (int i = 0; i < 3; ++i) {
      const auto stepping = (tv[i] - epsv) <= tmin;
      vv[i] = xsimd::select(stepping, vv[i] + stepv[i], vv[i]);
      facev[i] = xsimd::select(stepping, facev[i] + stepv[i], facev[i]);
      tv[i] = xsimd::select(stepping, xsimd::select(vv[i] == lastv[i], inf, nextv[i]), tv[i]);
      nextv[i] = (facev[i] + stepv[i] - startv[i]) * invv[i];
    }
    const unsigned arrived =
        lane_bits<Arch>((vv[0] == lastv[0]) && (vv[1] == lastv[1]) && (vv[2] == lastv[2])) & active;
    if (arrived != 0) {
      store_state();
      for (unsigned bits = arrived; bits != 0; bits &= bits - 1) load_lane(static_cast<std::size_t>(std::countr_zero(bits)));
      if (active == 0) break;
      load_state();
    }
  }
  mark_step(parity ^ 1);  // the last step's marks (the loop left before marking them)
  return visits;
}

}  // namespace
}  // namespace sarmap::kernels
