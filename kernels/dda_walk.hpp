// Exact 3-D DDA (Amanatides & Woo) over a unit grid: the cells a segment
// passes through, from the one holding its start up to (not including) the
// one holding its end, as OctoMap's computeRayKeys defines a ray's free cells.
//
// Tie rule: where the segment crosses two or three cell faces at the same
// point (through an edge or a corner) it steps those axes together, so only
// cells the segment passes through with positive length are visited (the
// walk is 26-connected). Crossings closer than kDdaTieParameter of the
// segment's length count as the same point, which absorbs rounding in the
// crossing parameters. OctoMap instead steps one axis per iteration (highest
// axis first on ties), so it also marks one of the cells that only touch the edge.
// Termination is exact: each axis steps exactly |end - start| times, so the
// walk never overshoots nor misses the end cell, whatever the rounding.
//
// Crossing parameters are floats, in coordinates relative to the start's
// cell, so that a vector register holds twice as many rays as in doubles
// (ray_marking: 16 lanes on AVX-512 instead of 8). Relative to the start
// cell, faces are small integers and the start lies in [0, 1), so a
// parameter is within about 2.5e-7 of exact (a few roundings of 6e-8
// each); kDdaTieParameter is four times that, and the cells visited are
// those of the exact segment except where it passes within about
// kDdaTieParameter x its length of an edge or a corner (2e-4 cells on a
// 200-cell ray, 0.05 m voxels at 10 m). Cells themselves are integers and
// exact; the end is rounded to float relative to the start cell (about
// 6e-8 x its length), which moves the segment, not the walk's last cell.
//
// dda_setup() and dda_step() are the whole arithmetic; the scalar walk here
// and the vector walk of ray_marking (many rays in SIMD lanes) both use
// exactly these operations, so they visit the same cells bit for bit.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace sarmap::kernels {

// 2^-20: parameters closer than this are one crossing.
inline constexpr float kDdaTieParameter = 1.0f / 1048576.0f;
// 2^-24, the gap below 1.0f: dda_setup() keeps a start's place in its cell
// below 1 and a local end below 0 by this much (also ray_marking's vector set-up).
inline constexpr float kDdaBelowOneGap = 1.0f / 16777216.0f;

// A ray's walking state. Crossing parameters are fractions of the segment
// and are always recomputed from the face coordinate, never accumulated, so
// the state is a function of the current cell.
struct DdaState {
  std::int32_t v[3], last[3], step[3];  // cells, absolute
  float start[3];  // the start relative to its cell's low corner, in [0, 1)
  float face[3];   // the face the ray leaves the current cell through, relative to the start's cell
  float inv[3];    // 1 / (end - start) on axes that move, else 0
  float t[3];      // parameter of the next crossing per axis (+inf: the axis is done)
  float next[3];   // parameter of the crossing after it
  bool moves;      // false when start and end lie in the same cell (nothing to visit)
};

// start and end in cell units (coordinate / cell size: faces at integers).
inline DdaState dda_setup(const double start[3], const double end[3]) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  constexpr float kBelowOne = 1.0f - kDdaBelowOneGap;
  DdaState s;
  for (int i = 0; i < 3; ++i) {
    const double origin = std::floor(start[i]);
    s.v[i] = static_cast<std::int32_t>(origin);
    s.last[i] = static_cast<std::int32_t>(std::floor(end[i]));
    // start - floor(start) is exact in doubles and rounds once to float,
    // kept below 1 (a fraction within 3e-8 of 1 would round to 1).
    const float start_local = static_cast<float>(start[i] - origin);
    s.start[i] = start_local < kBelowOne ? start_local : kBelowOne;
    // An axis moves only if start and end lie in different cells; then the
    // local end is at least 1 or below 0, kept at least 2^-24 below 0 (a
    // tiny negative would round to -0), so end - start is never 0.
    s.step[i] = s.last[i] > s.v[i] ? 1 : (s.last[i] < s.v[i] ? -1 : 0);
    const float end_rounded = static_cast<float>(end[i] - origin);
    const float end_local = s.step[i] < 0 && end_rounded > -kDdaBelowOneGap ? -kDdaBelowOneGap : end_rounded;
    s.face[i] = s.step[i] > 0 ? 1.0f : 0.0f;
    s.inv[i] = s.step[i] != 0 ? 1.0f / (end_local - s.start[i]) : 0.0f;
    s.t[i] = s.step[i] != 0 ? (s.face[i] - s.start[i]) * s.inv[i] : kInf;
    s.next[i] = (s.face[i] + static_cast<float>(s.step[i]) - s.start[i]) * s.inv[i];
  }
  s.moves = s.step[0] != 0 || s.step[1] != 0 || s.step[2] != 0;
  return s;
}

// One step to the next cell; returns false once the end cell is reached.
// Branch-free: which axes step is data-dependent and would mispredict about
// once per cell, so the selects compile to blends. The candidate next
// crossings are computed before the selection is known, so the chain carried
// from one cell to the next is only min, compare, select.
inline bool dda_step(DdaState& s) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const float t01 = s.t[0] < s.t[1] ? s.t[0] : s.t[1];  // std::fmin would be a libm call
  const float tmin = t01 < s.t[2] ? t01 : s.t[2];
  for (int i = 0; i < 3; ++i) {
    const bool step = s.t[i] - kDdaTieParameter <= tmin;
    s.v[i] += step ? s.step[i] : 0;
    s.face[i] += step ? static_cast<float>(s.step[i]) : 0.0f;
    s.t[i] = step ? (s.v[i] == s.last[i] ? kInf : s.next[i]) : s.t[i];
    s.next[i] = (s.face[i] + static_cast<float>(s.step[i]) - s.start[i]) * s.inv[i];
  }
  return !(s.v[0] == s.last[0] && s.v[1] == s.last[1] && s.v[2] == s.last[2]);
}

// Calls visit(x, y, z) for every cell of the walk; visit returns false to stop
// early. Returns the number of cells visited.
template <class Visit>
inline std::size_t dda_walk(const double start[3], const double end[3], Visit&& visit) {
  DdaState s = dda_setup(start, end);
  if (!s.moves) return 0;
  std::size_t visited = 0;
  // (Kept as one function over locals: a resumable walker object to
  // interleave rays in scalar code measured slower, its state went through
  // memory. ray_marking interleaves rays in SIMD lanes instead.)
  do {
    ++visited;
    if (!visit(s.v[0], s.v[1], s.v[2])) return visited;
  } while (dda_step(s));
  return visited;
}

}  // namespace sarmap::kernels
