// Dispatch and row parallelism of the kNN kernel, and its scalar reference
// (see knn.hpp).
#include "kernels/knn.hpp"

#include <algorithm>
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
}

}  // namespace

void knn(const float* points, std::size_t stride, std::size_t count, std::size_t dim, std::size_t k, SimdLevel level,
         KnnWorkspace& workspace, std::uint32_t* idx) {
  check(count, dim, k);
  if (!simd_level_supported(level)) throw std::invalid_argument("knn: instruction set not supported by this CPU");
  pack_points(points, stride, count, dim, level, workspace.panels, workspace.norms, workspace.centre);
  const detail::KnnArgs args{points,      stride, count, dim, k, workspace.panels.data(), workspace.norms.data(),
                             workspace.centre.data(), idx};
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
