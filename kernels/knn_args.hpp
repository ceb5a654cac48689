// What the dispatching code hands a per-instruction-set kNN kernel (internal
// to kernels/).
#pragma once

#include <cstddef>
#include <cstdint>

namespace sarmap::kernels::detail {

struct KnnArgs {
  const float* points = nullptr;  // count x dim, row stride `stride`, in the caller's order
  std::size_t stride = 0;
  std::size_t count = 0;
  std::size_t dim = 0;
  std::size_t k = 0;
  const float* panels = nullptr;  // the same points packed by pack_points(), in visit order
  const float* norms = nullptr;   // their squared norms, +inf padded
  const float* centre = nullptr;  // the mean pack_points() subtracted
  // Per panel, the bounding box of its points (lower corner, upper corner;
  // dim floats each, centred like the panels) and their largest length:
  // a tile of rows skips a panel that cannot hold a neighbour of any row.
  const float* panel_boxes = nullptr;
  const float* panel_max_radius = nullptr;
  float max_radius = 0.0f;  // the largest of panel_max_radius: every point's length, rounded up
  std::uint32_t* idx = nullptr;   // count x k, rows and ids in the caller's indices
  // Caller's index of each position of the panels (points packed in a visit
  // order), or nullptr when the panels hold the points in the caller's order.
  const std::uint32_t* original = nullptr;
  // panel_boxes dimension by dimension (KnnWorkspace::panel_boxes_by_dim),
  // `panel_stride` floats per corner and dimension; nullptr when the kernel
  // tests panels one at a time instead.
  const float* panel_boxes_by_dim = nullptr;
  std::size_t panel_stride = 0;
  // Per group of kKnnPanelsPerGroup panels, their common box and largest
  // length (as panel_boxes and panel_max_radius); nullptr when the kernel
  // tests every panel on its own.
  const float* group_boxes = nullptr;
  const float* group_max_radius = nullptr;
};

// Neighbours of rows [begin, end).
using KnnRowsFn = void (*)(const KnnArgs&, std::size_t begin, std::size_t end);

void knn_rows_sse42(const KnnArgs&, std::size_t, std::size_t);
void knn_rows_avx2(const KnnArgs&, std::size_t, std::size_t);
void knn_rows_avx512(const KnnArgs&, std::size_t, std::size_t);

}  // namespace sarmap::kernels::detail
