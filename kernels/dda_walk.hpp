// Exact 3-D DDA (Amanatides & Woo) over a unit grid: the cells a segment
// passes through, from the one holding its start up to (not including) the
// one holding its end, as OctoMap's computeRayKeys defines a ray's free cells.
//
// Tie rule: where the segment crosses two or three cell faces at the same
// point (through an edge or a corner) it steps those axes together, so only
// cells the segment passes through with positive length are visited (the
// walk is 26-connected). Crossings closer than kDdaTieTolerance cell of path
// length count as the same point, which absorbs rounding in the crossing
// parameters. OctoMap instead steps one axis per iteration (highest axis
// first on ties), so it also marks one of the cells that only touch the edge.
// Termination is exact: each axis steps exactly |end - start| times, so the
// walk never overshoots nor misses the end cell, whatever the rounding.
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

inline constexpr double kDdaTieTolerance = 1e-9;

// A ray's walking state. Crossing parameters are fractions of the segment
// and are always recomputed from the face coordinate, never accumulated, so
// the state is a function of the current cell.
struct DdaState {
  std::int32_t v[3], last[3], step[3];
  double face[3];  // the face the ray leaves the current cell through, as a coordinate
  double inv[3];   // 1 / (end - start) on axes that move, else 0
  double t[3];     // parameter of the next crossing per axis (+inf: the axis is done)
  double next[3];  // parameter of the crossing after it
  double eps;      // the tie tolerance as a parameter
  bool moves;      // false when start and end lie in the same cell (nothing to visit)
};

// start and end in cell units (coordinate / cell size: faces at integers).
inline DdaState dda_setup(const double start[3], const double end[3]) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  DdaState s;
  double length2 = 0;
  for (int i = 0; i < 3; ++i) {
    s.v[i] = static_cast<std::int32_t>(std::floor(start[i]));
    s.last[i] = static_cast<std::int32_t>(std::floor(end[i]));
    const double d = end[i] - start[i];
    length2 += d * d;
    // An axis moves only if start and end lie in different slabs; then d != 0.
    s.step[i] = s.last[i] > s.v[i] ? 1 : (s.last[i] < s.v[i] ? -1 : 0);
    s.face[i] = static_cast<double>(s.v[i] + (s.step[i] > 0 ? 1 : 0));
    s.inv[i] = s.step[i] != 0 ? 1.0 / d : 0.0;
    s.t[i] = s.step[i] != 0 ? (s.face[i] - start[i]) * s.inv[i] : kInf;
    s.next[i] = (s.face[i] + s.step[i] - start[i]) * s.inv[i];
  }
  s.moves = s.step[0] != 0 || s.step[1] != 0 || s.step[2] != 0;
  // Parameters are fractions of the segment; the tolerance is in cells of path.
  s.eps = s.moves ? kDdaTieTolerance / std::sqrt(length2) : 0.0;
  return s;
}

// One step to the next cell; returns false once the end cell is reached.
// Branch-free: which axes step is data-dependent and would mispredict about
// once per cell, so the selects compile to blends. The candidate next
// crossings are computed before the selection is known, so the chain carried
// from one cell to the next is only min, compare, select.
inline bool dda_step(DdaState& s, const double start[3]) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double t01 = s.t[0] < s.t[1] ? s.t[0] : s.t[1];  // std::fmin would be a libm call
  const double tmin = t01 < s.t[2] ? t01 : s.t[2];
  for (int i = 0; i < 3; ++i) {
    const bool step = s.t[i] - s.eps <= tmin;
    s.v[i] += step ? s.step[i] : 0;
    s.face[i] += step ? static_cast<double>(s.step[i]) : 0.0;
    s.t[i] = step ? (s.v[i] == s.last[i] ? kInf : s.next[i]) : s.t[i];
    s.next[i] = (s.face[i] + s.step[i] - start[i]) * s.inv[i];
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
  } while (dda_step(s, start));
  return visited;
}

}  // namespace sarmap::kernels
