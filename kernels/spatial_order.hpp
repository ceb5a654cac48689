// A visiting order for the kNN kernel: points sorted along a Hilbert curve of
// three of their coordinates, so that points close in the list are close in
// space. DGCNN's blocks come in random order; in this order each
// point's near neighbours sit in the first panels the kernel visits.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/aligned_buffer.hpp"

namespace sarmap::kernels {

// order[0..count) = the point indices sorted by the Hilbert index of
// (x, y, z) = points[i * stride + 0..2], quantised to 10 bits per axis over
// the points' own bounding box; equal codes keep index order. Non-finite
// coordinates count as the box's lower corner. `keys` is scratch (grow-only,
// 2 * count).
void spatial_order(const float* points, std::size_t stride, std::size_t count, AlignedBuffer<std::uint64_t>& keys,
                   std::uint32_t* order);

}  // namespace sarmap::kernels
