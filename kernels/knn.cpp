// Dispatch and row parallelism of the kNN kernel, and its scalar reference
// (see knn.hpp).
#include "kernels/knn.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "kernels/exact_distance.hpp"
#include "kernels/knn_args.hpp"
#include "kernels/packed_matrix.hpp"

namespace sarmap::kernels {
namespace {

constexpr std::size_t kChunkRows = 48;  // a multiple of both tile heights (6, 12)

bool uses_gaps_up_front(std::size_t panel_count, std::size_t dim) {
  return dim <= kKnnGapsUpFrontMaxDim && panel_count <= kKnnGapsUpFrontMaxPanels;
}

bool uses_panel_groups(std::size_t panel_count, std::size_t dim) {
  return !uses_gaps_up_front(panel_count, dim) && panel_count <= kKnnMaxGroupedPanels;
}

// Floats per corner and dimension in panel_boxes_by_dim: whole vectors of
// the widest instruction set.
std::size_t panel_stride(std::size_t panel_count) { return (panel_count + 15) / 16 * 16; }

// The bounding box and largest length of each packed panel's points
// (padding lanes excluded), in the panels' own centred floats.
void panel_bounds(std::size_t count, std::size_t dim, SimdLevel level, KnnWorkspace& ws) {
  const std::size_t nr = static_cast<std::size_t>(panel_width(level));
  const std::size_t panel_count = (count + nr - 1) / nr;
  ws.panel_boxes.resize(panel_count * 2 * dim);
  ws.panel_max_radius.resize(panel_count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, panel_count, 16), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      const float* panel = ws.panels.data() + p * nr * dim;
      const std::size_t lanes = std::min(nr, count - p * nr);
      float* lo = ws.panel_boxes.data() + p * 2 * dim;
      float* hi = lo + dim;
      // Lane by lane, so the inner loop runs along the dimensions (a vector
      // min and max) rather than reducing across a dimension's lanes.
      for (std::size_t c = 0; c < dim; ++c) lo[c] = hi[c] = panel[c * nr];
      for (std::size_t l = 1; l < lanes; ++l) {
        for (std::size_t c = 0; c < dim; ++c) {
          lo[c] = std::min(lo[c], panel[c * nr + l]);
          hi[c] = std::max(hi[c], panel[c * nr + l]);
        }
      }
      float max_norm = 0.0f;
      for (std::size_t l = 0; l < lanes; ++l) max_norm = std::max(max_norm, ws.norms[p * nr + l]);
      // Only feeds a rounding allowance; one ulp up keeps it an upper bound.
      ws.panel_max_radius[p] = std::nextafter(std::sqrt(max_norm), std::numeric_limits<float>::infinity());
    }
  });
  if (uses_panel_groups(panel_count, dim)) {
    const std::size_t group_count = (panel_count + kKnnPanelsPerGroup - 1) / kKnnPanelsPerGroup;
    ws.group_boxes.resize(group_count * 2 * dim);
    ws.group_max_radius.resize(group_count);
    for (std::size_t g = 0; g < group_count; ++g) {
      const std::size_t first = g * kKnnPanelsPerGroup, last = std::min(panel_count, first + kKnnPanelsPerGroup);
      float* lo = ws.group_boxes.data() + g * 2 * dim;
      float* hi = lo + dim;
      std::copy_n(ws.panel_boxes.data() + first * 2 * dim, 2 * dim, lo);
      float radius = ws.panel_max_radius[first];
      for (std::size_t p = first + 1; p < last; ++p) {
        const float* box = ws.panel_boxes.data() + p * 2 * dim;
        for (std::size_t c = 0; c < dim; ++c) {
          lo[c] = std::min(lo[c], box[c]);
          hi[c] = std::max(hi[c], box[dim + c]);
        }
        radius = std::max(radius, ws.panel_max_radius[p]);
      }
      ws.group_max_radius[g] = radius;
    }
  }
  if (uses_gaps_up_front(panel_count, dim)) {
    const std::size_t stride = panel_stride(panel_count);
    ws.panel_boxes_by_dim.resize(stride * 2 * dim);
    // The lanes past the last panel are never read as results; zeros keep them finite.
    std::fill_n(ws.panel_boxes_by_dim.data(), stride * 2 * dim, 0.0f);
    for (std::size_t p = 0; p < panel_count; ++p) {
      const float* box = ws.panel_boxes.data() + p * 2 * dim;
      for (std::size_t c = 0; c < dim; ++c) {
        ws.panel_boxes_by_dim[(2 * c) * stride + p] = box[c];
        ws.panel_boxes_by_dim[(2 * c + 1) * stride + p] = box[dim + c];
      }
    }
  }
}

detail::KnnRowsFn rows_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return detail::knn_rows_avx512;
    case SimdLevel::Avx2: return detail::knn_rows_avx2;
    case SimdLevel::Sse42: break;
  }
  return detail::knn_rows_sse42;
}

void check(std::size_t count, std::size_t dim, std::size_t k) {
  if (k < 1 || k > kKnnMaxK) throw std::invalid_argument("knn: k must be 1.." + std::to_string(kKnnMaxK));
  if (dim < 1 || dim > kKnnMaxDim) throw std::invalid_argument("knn: dim must be 1.." + std::to_string(kKnnMaxDim));
  if (count < 1) throw std::invalid_argument("knn: no points");
  if (count > kKnnMaxCount) throw std::invalid_argument("knn: more than " + std::to_string(kKnnMaxCount) + " points");
}

}  // namespace

void knn(const float* points, std::size_t stride, std::size_t count, std::size_t dim, std::size_t k, SimdLevel level,
         KnnWorkspace& workspace, std::uint32_t* idx, const std::uint32_t* visit_order) {
  check(count, dim, k);
  if (!simd_level_supported(level)) throw std::invalid_argument("knn: instruction set not supported by this CPU");
  if (visit_order != nullptr) {
    // Gather the rows in visit order; the kernel maps positions back.
    // A repeated index would leave some caller's row without neighbours.
    workspace.gathered.resize(count * dim);
    workspace.visited.resize(count);
    std::fill_n(workspace.visited.data(), count, std::uint8_t{0});
    float* gathered = workspace.gathered.data();
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t from = visit_order[i];
      if (from >= count || workspace.visited[from] != 0) {
        throw std::invalid_argument("knn: the visit order is not a permutation of the points (index " +
                                    std::to_string(from) + " at position " + std::to_string(i) + ")");
      }
      workspace.visited[from] = 1;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 512), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        std::copy_n(points + static_cast<std::size_t>(visit_order[i]) * stride, dim, gathered + i * dim);
      }
    });
    pack_points(gathered, dim, count, dim, level, workspace.panels, workspace.norms, workspace.centre);
  } else {
    pack_points(points, stride, count, dim, level, workspace.panels, workspace.norms, workspace.centre);
  }
  panel_bounds(count, dim, level, workspace);
  detail::KnnArgs args{points,
                             stride,
                             count,
                             dim,
                             k,
                             workspace.panels.data(),
                             workspace.norms.data(),
                             workspace.centre.data(),
                             workspace.panel_boxes.data(),
                             workspace.panel_max_radius.data(),
                             *std::max_element(workspace.panel_max_radius.data(),
                                               workspace.panel_max_radius.data() + workspace.panel_max_radius.size()),
                             idx,
                             visit_order};
  const std::size_t panel_count = workspace.panel_max_radius.size();
  if (uses_gaps_up_front(panel_count, dim)) {
    args.panel_boxes_by_dim = workspace.panel_boxes_by_dim.data();
    args.panel_stride = panel_stride(panel_count);
  }
  if (uses_panel_groups(panel_count, dim)) {
    args.group_boxes = workspace.group_boxes.data();
    args.group_max_radius = workspace.group_max_radius.data();
  }
  const detail::KnnRowsFn fn = rows_fn(level);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, (count + kChunkRows - 1) / kChunkRows, 1),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c != r.end(); ++c) {
          fn(args, c * kChunkRows, std::min(count, (c + 1) * kChunkRows));
        }
      },
      tbb::simple_partitioner());
}

void knn_reference(const float* points, std::size_t stride, std::size_t count, std::size_t dim, std::size_t k,
                   std::uint32_t* idx) {
  check(count, dim, k);
  std::vector<double> dist(count);
  std::vector<std::uint32_t> order(count);
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t j = 0; j < count; ++j) {
      dist[j] = exact_squared_distance(points + i * stride, points + j * stride, dim);
    }
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return dist[a] < dist[b]; });
    for (std::size_t j = 0; j < k; ++j) idx[i * k + j] = j < count ? order[j] : order[0];
  }
}

}  // namespace sarmap::kernels
