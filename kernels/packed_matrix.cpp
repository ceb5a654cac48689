// Packing of weights and points into GEMM panels (see packed_matrix.hpp).
#include "kernels/packed_matrix.hpp"

#include <algorithm>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sarmap::kernels {

PackedMatrix::PackedMatrix(const float* weights, const float* bias, std::size_t rows, std::size_t cols,
                           SimdLevel level)
    : rows_(rows), cols_(cols), nr_(static_cast<std::size_t>(kernels::panel_width(level))), level_(level) {
  const std::size_t panels = panel_count();
  data_.resize(panels * nr_ * cols_);
  bias_.resize(panels * nr_);
  for (std::size_t p = 0; p < panels; ++p) {
    float* dst = data_.data() + p * nr_ * cols_;
    for (std::size_t c = 0; c < cols_; ++c) {
      for (std::size_t r = 0; r < nr_; ++r) {
        const std::size_t row = p * nr_ + r;
        dst[c * nr_ + r] = row < rows_ ? weights[row * cols_ + c] : 0.0f;
      }
    }
  }
  for (std::size_t r = 0; r < panels * nr_; ++r) bias_[r] = (bias != nullptr && r < rows_) ? bias[r] : 0.0f;
}

void pack_points(const float* points, std::size_t stride, std::size_t count, std::size_t dim, SimdLevel level,
                 AlignedBuffer<float>& panels, AlignedBuffer<float>& norms, AlignedBuffer<float>& centre) {
  centre.resize(dim);
  // Summed point by point, a block of dimensions at a time: each dimension's
  // sum is still added in point order (the same double as a column loop), but
  // the block's sums are independent chains instead of one long one per
  // dimension, and the points are read along their rows.
  constexpr std::size_t kSumBlock = 64;
  for (std::size_t c0 = 0; c0 < dim; c0 += kSumBlock) {
    const std::size_t width = std::min(kSumBlock, dim - c0);
    double sum[kSumBlock] = {};
    for (std::size_t i = 0; i < count; ++i) {
      const float* src = points + i * stride + c0;
      for (std::size_t c = 0; c < width; ++c) sum[c] += src[c];
    }
    for (std::size_t c = 0; c < width; ++c) {
      centre[c0 + c] = count > 0 ? static_cast<float>(sum[c] / static_cast<double>(count)) : 0.0f;
    }
  }
  const std::size_t nr = static_cast<std::size_t>(panel_width(level));
  const std::size_t panel_count = (count + nr - 1) / nr;
  panels.resize(panel_count * nr * dim);
  norms.resize(panel_count * nr);
  const float* const mean = centre.data();
  // Panels are independent; a grain of 16 keeps a small cloud on one thread.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, panel_count, 16), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      float* dst = panels.data() + p * nr * dim;
      for (std::size_t r = 0; r < nr; ++r) {
        const std::size_t point = p * nr + r;
        if (point < count) {
          const float* src = points + point * stride;
          float norm = 0.0f;
          for (std::size_t c = 0; c < dim; ++c) {
            const float v = src[c] - mean[c];
            dst[c * nr + r] = v;
            norm += v * v;
          }
          norms[point] = norm;
        } else {
          for (std::size_t c = 0; c < dim; ++c) dst[c * nr + r] = 0.0f;
          // Padding columns can never be selected as neighbours.
          norms[point] = std::numeric_limits<float>::infinity();
        }
      }
    }
  });
}

}  // namespace sarmap::kernels
