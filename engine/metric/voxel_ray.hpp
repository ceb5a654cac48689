// Exact 3-D DDA (Amanatides & Woo) over the voxel grid: the voxels a segment
// passes through, from the one holding its start up to (not including) the
// one holding its end, as OctoMap's computeRayKeys defines a ray's free cells.
//
// Tie rule: where the segment crosses two or three voxel faces at the same
// point (through an edge or a corner) it steps those axes together, so only
// voxels the segment passes through with positive length are visited (the
// walk is 26-connected). Crossings closer than kRayTieTolerance voxel of path
// length count as the same point, which absorbs rounding in the crossing
// parameters. OctoMap instead steps one axis per iteration (highest axis
// first on ties), so it also marks one of the voxels that only touch the edge.
// Termination is exact: each axis steps exactly |end - start| times, so the
// walk never overshoots nor misses the end voxel, whatever the rounding.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/metric/voxel_key.hpp"

namespace sarmap::metric {

inline constexpr double kRayTieTolerance = 1e-9;

// start and end are in voxel units (coordinate / resolution, so voxel faces
// are at integers). visit(const VoxelKey&) returns false to stop early.
// Returns the number of voxels visited.
template <class Visit>
inline std::size_t walk_ray(const double start[3], const double end[3], Visit&& visit) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::int32_t v[3], last[3], step[3];
  double inv[3], face[3], t[3], next[3];
  double length2 = 0;
  for (int i = 0; i < 3; ++i) {
    v[i] = static_cast<std::int32_t>(std::floor(start[i]));
    last[i] = static_cast<std::int32_t>(std::floor(end[i]));
    const double d = end[i] - start[i];
    length2 += d * d;
    // An axis moves only if start and end lie in different slabs; then d != 0.
    step[i] = last[i] > v[i] ? 1 : (last[i] < v[i] ? -1 : 0);
    // The face the ray leaves the current voxel through, as a coordinate.
    face[i] = static_cast<double>(v[i] + (step[i] > 0 ? 1 : 0));
    inv[i] = step[i] != 0 ? 1.0 / d : 0.0;
    t[i] = step[i] != 0 ? (face[i] - start[i]) * inv[i] : kInf;
    next[i] = (face[i] + step[i] - start[i]) * inv[i];
  }
  if (step[0] == 0 && step[1] == 0 && step[2] == 0) return 0;
  // Parameters are fractions of the segment; the tolerance is in voxels of path.
  const double eps = kRayTieTolerance / std::sqrt(length2);
  std::size_t visited = 0;
  // Branch-free stepping: which axes step is data-dependent and would
  // mispredict about once per voxel, so the selects compile to blends. The
  // candidate next crossings are computed before the selection is known, so
  // the chain carried from one voxel to the next is only min, compare, select.
  // (Kept as locals in one function: a resumable walker object to interleave
  // rays measured slower, its state went through memory.)
  while (true) {
    ++visited;
    if (!visit(VoxelKey{v[0], v[1], v[2]})) return visited;
    const double t01 = t[0] < t[1] ? t[0] : t[1];  // std::fmin would be a libm call
    const double tmin = t01 < t[2] ? t01 : t[2];
    for (int i = 0; i < 3; ++i) {
      const bool s = t[i] - eps <= tmin;
      v[i] += s ? step[i] : 0;
      face[i] += s ? static_cast<double>(step[i]) : 0.0;
      t[i] = s ? (v[i] == last[i] ? kInf : next[i]) : t[i];
      next[i] = (face[i] + step[i] - start[i]) * inv[i];
    }
    if (v[0] == last[0] && v[1] == last[1] && v[2] == last[2]) return visited;
  }
}

}  // namespace sarmap::metric
