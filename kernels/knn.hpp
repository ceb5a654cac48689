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
  AlignedBuffer<float> gathered;         // the points in visit order, when one is given
  AlignedBuffer<std::uint8_t> visited;   // checks that the visit order is a permutation
  AlignedBuffer<float> panels;
  AlignedBuffer<float> norms;
  AlignedBuffer<float> centre;
  AlignedBuffer<float> panel_boxes;     // per panel: lower then upper corner (dim each)
  AlignedBuffer<float> panel_max_radius;  // per panel: its largest length (rounded up)
  // The same boxes dimension by dimension (all panels' lower corners in
  // dimension 0, then their upper corners, then dimension 1, ...), for
  // low-dimensional points only (knn_limits.hpp).
  AlignedBuffer<float> panel_boxes_by_dim;
  // Per group of kKnnPanelsPerGroup panels, their common box and largest
  // length, laid out as panel_boxes and panel_max_radius (knn_limits.hpp).
  AlignedBuffer<float> group_boxes;
  AlignedBuffer<float> group_max_radius;

  // Bytes held by all of the above (a caller's working-set report).
  std::size_t bytes() const {
    return gathered.capacity_bytes() + visited.capacity_bytes() + panels.capacity_bytes() + norms.capacity_bytes() +
           centre.capacity_bytes() + panel_boxes.capacity_bytes() + panel_max_radius.capacity_bytes() +
           panel_boxes_by_dim.capacity_bytes() + group_boxes.capacity_bytes() + group_max_radius.capacity_bytes();
  }
};

// idx[i * k + j] = j-th nearest of point i (count x k). points: count x dim
// floats with row stride `stride`. With count < k the list holds every point
// and then repeats the nearest. Requires 1 <= k <= kKnnMaxK,
// 1 <= dim <= kKnnMaxDim, 1 <= count <= kKnnMaxCount (std::invalid_argument
// otherwise).
//
// visit_order (optional, a permutation of 0..count-1) lists the points so
// that near points are near each other, e.g. spatial_order() of their xyz:
// the kernel then meets each point's near neighbours first and skips most of
// the rest, several times faster than in random order. The neighbours are the
// same with or without it (it changes the visiting order, not the ranking).
void knn(const float* points, std::size_t stride, std::size_t count, std::size_t dim, std::size_t k, SimdLevel level,
         KnnWorkspace& workspace, std::uint32_t* idx, const std::uint32_t* visit_order = nullptr);

// Scalar reference: exact differences in double, ties by index. knn() gives
// the same lists.
void knn_reference(const float* points, std::size_t stride, std::size_t count, std::size_t dim, std::size_t k,
                   std::uint32_t* idx);

}  // namespace sarmap::kernels
