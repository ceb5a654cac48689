// Dispatch and point parallelism of the EdgeConv kernels, and their scalar
// references (see edge_conv.hpp).
#include "kernels/edge_conv.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "kernels/edge_conv_args.hpp"

namespace sarmap::kernels {
namespace {

constexpr std::size_t kChunkPoints = 48;

detail::EdgeConvPointsFn edge_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return detail::edge_conv_points_avx512;
    case SimdLevel::Avx2: return detail::edge_conv_points_avx2;
    case SimdLevel::Sse42: break;
  }
  return detail::edge_conv_points_sse42;
}

detail::EdgeConvPointsFn gather_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return detail::gather_max_points_avx512;
    case SimdLevel::Avx2: return detail::gather_max_points_avx2;
    case SimdLevel::Sse42: break;
  }
  return detail::gather_max_points_sse42;
}

void run_chunks(std::size_t count, detail::EdgeConvPointsFn fn, const detail::EdgeConvArgs& args) {
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, (count + kChunkPoints - 1) / kChunkPoints, 1),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c != r.end(); ++c) {
          fn(args, c * kChunkPoints, std::min(count, (c + 1) * kChunkPoints));
        }
      },
      tbb::simple_partitioner());
}

float act(float v, float slope) { return v >= 0.0f ? v : slope * v; }

}  // namespace

void edge_conv_max(const float* a, const float* b, std::size_t ld_ab, std::size_t count, std::size_t hidden,
                   const std::uint32_t* idx, std::size_t k, float slope1, const PackedMatrix& w2, float slope2,
                   float* out, std::size_t ldo) {
  if (hidden < 1 || hidden > kEdgeMaxHidden || w2.cols() != hidden || w2.rows() > kEdgeMaxOut || k < 1 ||
      k > kEdgeMaxK) {
    throw std::invalid_argument("edge_conv_max: sizes outside the kernel's limits");
  }
  if (!simd_level_supported(w2.level())) throw std::invalid_argument("edge_conv_max: unsupported instruction set");
  detail::EdgeConvArgs args{a, b, ld_ab, count, hidden, idx, k, slope1, &w2, slope2, out, ldo};
  run_chunks(count, edge_fn(w2.level()), args);
}

void gather_max(const float* a, const float* b, std::size_t ld_ab, std::size_t count, std::size_t channels,
                const std::uint32_t* idx, std::size_t k, float slope, SimdLevel level, float* out, std::size_t ldo) {
  if (k < 1) throw std::invalid_argument("gather_max: k must be at least 1");
  if (!simd_level_supported(level)) throw std::invalid_argument("gather_max: unsupported instruction set");
  detail::EdgeConvArgs args{a, b, ld_ab, count, channels, idx, k, slope, nullptr, 1.0f, out, ldo};
  run_chunks(count, gather_fn(level), args);
}

void edge_conv_max_reference(const float* a, const float* b, std::size_t ld_ab, std::size_t count,
                             std::size_t hidden, const std::uint32_t* idx, std::size_t k, float slope1,
                             const float* w2, const float* bias2, std::size_t out_channels, float slope2, float* out,
                             std::size_t ldo) {
  std::vector<float> edge(hidden);
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t o = 0; o < out_channels; ++o) out[i * ldo + o] = -std::numeric_limits<float>::infinity();
    for (std::size_t j = 0; j < k; ++j) {
      const std::size_t n = idx[i * k + j];
      for (std::size_t h = 0; h < hidden; ++h) edge[h] = act(a[n * ld_ab + h] + b[i * ld_ab + h], slope1);
      for (std::size_t o = 0; o < out_channels; ++o) {
        double sum = bias2 != nullptr ? bias2[o] : 0.0;
        for (std::size_t h = 0; h < hidden; ++h) sum += static_cast<double>(w2[o * hidden + h]) * edge[h];
        out[i * ldo + o] = std::max(out[i * ldo + o], act(static_cast<float>(sum), slope2));
      }
    }
  }
}

void gather_max_reference(const float* a, const float* b, std::size_t ld_ab, std::size_t count, std::size_t channels,
                          const std::uint32_t* idx, std::size_t k, float slope, float* out, std::size_t ldo) {
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t c = 0; c < channels; ++c) {
      float best = -std::numeric_limits<float>::infinity();
      for (std::size_t j = 0; j < k; ++j) {
        best = std::max(best, act(a[idx[i * k + j] * ld_ab + c] + b[i * ld_ab + c], slope));
      }
      out[i * ldo + c] = best;
    }
  }
}

}  // namespace sarmap::kernels
