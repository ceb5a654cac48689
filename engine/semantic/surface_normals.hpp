// Surface normals by PCA over neighbours, for the geometric classifier. The
// neighbourhood of a point is the 3 x 3 x 3 cells around its own cell of a
// regular grid: per-cell sums are pooled, so the cost is one small eigen
// problem per occupied cell however dense the scan is close to the sensor
// (a 320 x 240 depth frame puts thousands of points in a 5 cm disc at 0.3 m).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/point_buffer.hpp"

namespace sarmap {

struct SurfaceNormalSettings {
  double cell = 0.05;          // metres; the neighbourhood spans 3 cells per axis
  std::size_t min_points = 5;  // fewer pooled points: no normal (valid = 0)
  // Above this curvature the neighbourhood spans an edge and the cell's own
  // points are fitted instead.
  double max_curvature = 0.05;
};

struct SurfaceNormals {
  // Per point, unit length, oriented with nz >= 0 (only the slope matters here).
  std::vector<float> nx, ny, nz;
  // Smallest eigenvalue over their sum: 0 on a plane, 1/3 for a blob.
  std::vector<float> curvature;
  std::vector<std::uint8_t> valid;
};

// Points beyond 10 km of the origin (which the metric map rejects) get no
// normal. Throws sarmap::Error(InvalidArgument) for a cell under 1 cm or a
// non-finite point (the pipeline removes those before classifying).
SurfaceNormals estimate_surface_normals(const PointBuffer& points, const SurfaceNormalSettings& settings);

}  // namespace sarmap
