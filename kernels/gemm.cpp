// Dispatch of the GEMM kernels to the instruction set of the packed weights,
// row-chunk parallelism, and the scalar references (see gemm.hpp).
#include "kernels/gemm.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "kernels/gemm_args.hpp"

namespace sarmap::kernels {
namespace {

// Rows per parallel task: a multiple of every tile height (6, 12), small
// enough to balance two threads on a 4096-point block, large enough that a
// task's x rows stay in L2 while every weight panel passes over them.
constexpr std::size_t kChunkRows = 96;

detail::GemmRowsFn rows_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return detail::gemm_rows_avx512;
    case SimdLevel::Avx2: return detail::gemm_rows_avx2;
    case SimdLevel::Sse42: break;
  }
  return detail::gemm_rows_sse42;
}

detail::GemmColumnMaxFn column_max_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return detail::gemm_column_max_avx512;
    case SimdLevel::Avx2: return detail::gemm_column_max_avx2;
    case SimdLevel::Sse42: break;
  }
  return detail::gemm_column_max_sse42;
}

void check_level(const PackedMatrix& w) {
  if (!simd_level_supported(w.level())) {
    throw std::invalid_argument("gemm: weights packed for an instruction set this CPU lacks");
  }
}

std::size_t chunk_count(std::size_t m) { return (m + kChunkRows - 1) / kChunkRows; }

}  // namespace

void gemm_bias_act(const float* x, std::size_t ldx, std::size_t m, const PackedMatrix& w, float slope, float* y,
                   std::size_t ldy) {
  gemm_bias_act(x, ldx, m, w, w.bias(), slope, y, ldy);
}

void gemm_bias_act(const float* x, std::size_t ldx, std::size_t m, const PackedMatrix& w, const float* bias,
                   float slope, float* y, std::size_t ldy) {
  check_level(w);
  const detail::GemmArgs args{x, ldx, &w, bias, slope, y, ldy};
  const detail::GemmRowsFn fn = rows_fn(w.level());
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, chunk_count(m), 1),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c != r.end(); ++c) fn(args, c * kChunkRows, std::min(m, (c + 1) * kChunkRows));
      },
      tbb::simple_partitioner());
}

void gemm_column_max(const float* x, std::size_t ldx, std::size_t m, const PackedMatrix& w, float* colmax) {
  check_level(w);
  const detail::GemmArgs args{x, ldx, &w, w.bias(), 1.0f, nullptr, 0};
  const detail::GemmColumnMaxFn fn = column_max_fn(w.level());
  const std::size_t chunks = chunk_count(m);
  const std::size_t width = w.panel_count() * w.panel_width();
  // One partial maximum per chunk, merged afterwards: max is exact, so the
  // result does not depend on how chunks map to threads. The buffer belongs
  // to the calling thread and only grows.
  thread_local AlignedBuffer<float> partial;
  partial.resize(chunks * width);
  std::fill(partial.data(), partial.data() + chunks * width, -std::numeric_limits<float>::infinity());
  float* base = partial.data();
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, chunks, 1),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c != r.end(); ++c) {
          fn(args, c * kChunkRows, std::min(m, (c + 1) * kChunkRows), base + c * width);
        }
      },
      tbb::simple_partitioner());
  for (std::size_t o = 0; o < w.rows(); ++o) {
    float best = -std::numeric_limits<float>::infinity();
    for (std::size_t c = 0; c < chunks; ++c) best = std::max(best, base[c * width + o]);
    colmax[o] = best;
  }
}

void gemm_bias_act_reference(const float* x, std::size_t ldx, std::size_t m, const float* w, const float* bias,
                             std::size_t rows, std::size_t cols, float slope, float* y, std::size_t ldy) {
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t o = 0; o < rows; ++o) {
      double sum = bias != nullptr ? bias[o] : 0.0;
      for (std::size_t c = 0; c < cols; ++c) sum += static_cast<double>(x[i * ldx + c]) * w[o * cols + c];
      const float v = static_cast<float>(sum);
      y[i * ldy + o] = v >= 0.0f ? v : slope * v;
    }
  }
}

void gemm_column_max_reference(const float* x, std::size_t ldx, std::size_t m, const float* w, std::size_t rows,
                               std::size_t cols, float* colmax) {
  for (std::size_t o = 0; o < rows; ++o) {
    double best = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < m; ++i) {
      double sum = 0.0;
      for (std::size_t c = 0; c < cols; ++c) sum += static_cast<double>(x[i * ldx + c]) * w[o * cols + c];
      best = std::max(best, sum);
    }
    colmax[o] = static_cast<float>(best);
  }
}

}  // namespace sarmap::kernels
