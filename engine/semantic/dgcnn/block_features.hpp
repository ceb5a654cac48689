// The per-point input features of one DGCNN block; the one definition is
// `block_features` in tools/python/dgcnn_reference.py and this must match it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/point_buffer.hpp"

namespace sarmap {

struct BlockFrame {
  double origin_x = 0.0, origin_y = 0.0;  // the cell's lower corner in xy
  double block_size = 1.0;                // metres
  double z_min = -0.5, z_max = 2.5;       // fixed height range of the world frame
};

// Features of `points[indices[i]]` in row i: 6 channels [x-cx, y-cy, z, nx, ny, nz]
// or, when `with_rgb` (the cloud must have colours), 9 channels
// [x-cx, y-cy, z, r, g, b, nx, ny, nz] with colours in [0, 1].
// Throws sarmap::Error on a non-positive block size or empty z range.
std::vector<float> block_features(const PointBuffer& points, std::span<const std::uint32_t> indices,
                                  const BlockFrame& frame, bool with_rgb);

}  // namespace sarmap
