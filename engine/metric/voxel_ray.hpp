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
  std::int32_t v[3], last[3], step[3], face[3];
  double inv[3], t[3];
  double length2 = 0;
  for (int i = 0; i < 3; ++i) {
    v[i] = static_cast<std::int32_t>(std::floor(start[i]));
    last[i] = static_cast<std::int32_t>(std::floor(end[i]));
    const double d = end[i] - start[i];
    length2 += d * d;
    // An axis moves only if start and end lie in different slabs; then d != 0.
    step[i] = last[i] > v[i] ? 1 : (last[i] < v[i] ? -1 : 0);
    face[i] = step[i] > 0 ? 1 : 0;  // offset of the face the ray leaves through
    inv[i] = step[i] != 0 ? 1.0 / d : 0.0;
    t[i] = step[i] != 0 ? (static_cast<double>(v[i] + face[i]) - start[i]) * inv[i] : kInf;
  }
  if (step[0] == 0 && step[1] == 0 && step[2] == 0) return 0;
  // Parameters are fractions of the segment; the tolerance is in voxels of path.
  const double eps = kRayTieTolerance / std::sqrt(length2);
  std::size_t visited = 0;
  while (true) {
    ++visited;
    if (!visit(VoxelKey{v[0], v[1], v[2]})) return visited;
    const double tmin = std::fmin(t[0], std::fmin(t[1], t[2])) + eps;
    const bool s0 = t[0] <= tmin, s1 = t[1] <= tmin, s2 = t[2] <= tmin;
    if (s0) {
      v[0] += step[0];
      t[0] = v[0] == last[0] ? kInf : (static_cast<double>(v[0] + face[0]) - start[0]) * inv[0];
    }
    if (s1) {
      v[1] += step[1];
      t[1] = v[1] == last[1] ? kInf : (static_cast<double>(v[1] + face[1]) - start[1]) * inv[1];
    }
    if (s2) {
      v[2] += step[2];
      t[2] = v[2] == last[2] ? kInf : (static_cast<double>(v[2] + face[2]) - start[2]) * inv[2];
    }
    if (v[0] == last[0] && v[1] == last[1] && v[2] == last[2]) return visited;
  }
}

}  // namespace sarmap::metric
