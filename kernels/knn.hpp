// k nearest neighbours of every point among the same points (squared
// Euclidean distance), as DGCNN's dynamic graph needs: a point is its own
// nearest neighbour, neighbours come nearest first, ties go to the smaller
// index. Parallel over rows with oneTBB; results do not depend on threads.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/aligned_buffer.hpp"
#include "kernels/knn_limits.hpp"
#include "kernels/simd_level.hpp"

namespace sarmap::kernels {

// Packed copies of the points; reused (grow-only) from call to call.
struct KnnWorkspace {
  AlignedBuffer<float> panels;
  AlignedBuffer<float> norms;
  AlignedBuffer<float> centre;
};

// idx[i * k + j] = j-th nearest of point i (count x k). points: count x dim
// floats with row stride `stride`. With count < k the list holds every point
// and then repeats the nearest. Requires 1 <= k <= kKnnMaxK,
// 1 <= dim <= kKnnMaxDim, count >= 1 (std::invalid_argument otherwise).
void knn(const float* points, std::size_t stride, std::size_t count, std::size_t dim, std::size_t k, SimdLevel level,
         KnnWorkspace& workspace, std::uint32_t* idx);

// Scalar reference: exact differences in double, ties by index. The kernel
// gives the same lists unless float rounding moves a point across kKnnExtra ranks.
void knn_reference(const float* points, std::size_t stride, std::size_t count, std::size_t dim, std::size_t k,
                   std::uint32_t* idx);

}  // namespace sarmap::kernels
