// The EdgeConv kernels written once over the xsimd architecture, compiled per
// instruction set by edge_conv_{sse42,avx2,avx512}.cpp.
//
// The first convolution of an EdgeConv acts on [x_j - x_i, x_i]; with
// W = [W1 W2] that is W1 x_j + (W2 - W1) x_i, so the caller computes the
// per-point terms a = W1 x and b = (W2 - W1) x + bias once (a GEMM), and an
// edge costs one gather-add. With BN folded into the weights, the activation
// after the second convolution is monotone, so max over neighbours commutes
// with it: the kernel keeps a running max of the raw second-convolution
// output and applies bias + LeakyReLU once per point. The N x k x 2C edge
// tensor never exists: a few points' edges live in an L1-sized tile.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include "kernels/edge_conv_args.hpp"
#include "kernels/edge_conv_limits.hpp"
#include "kernels/microkernel.hpp"

namespace sarmap::kernels {
namespace {

template <class Arch>
inline Batch<Arch> leaky(const Batch<Arch>& v, const Batch<Arch>& slope) {
  return xsimd::max(v, v * slope);
}

template <class Arch>
void edge_conv_points_impl(const detail::EdgeConvArgs& e, std::size_t begin, std::size_t end) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  constexpr std::size_t NR = 2 * L;
  constexpr int MR = tile_rows<Arch>();
  const PackedMatrix& w = *e.w2;
  const std::size_t k = e.k, hidden = e.hidden;
  const std::size_t width = w.panel_count() * NR;
  const std::size_t edge_floats = k * hidden;
  std::size_t tile_points = kEdgeTileFloats / edge_floats;
  if (tile_points < 1) tile_points = 1;
  if (tile_points > kEdgeMaxTilePoints) tile_points = kEdgeMaxTilePoints;

  alignas(64) float edges[kEdgeMaxK * kEdgeMaxHidden > kEdgeTileFloats ? kEdgeMaxK * kEdgeMaxHidden : kEdgeTileFloats];
  alignas(64) float maxima[kEdgeMaxTilePoints * (kEdgeMaxOut + 32)];
  const B slope1(e.slope1), slope2(e.slope2);
  const std::size_t hidden_vec = hidden - hidden % L;

  for (std::size_t first = begin; first < end; first += tile_points) {
    const std::size_t points = min_size(tile_points, end - first);
    // Edge features act1(a[j] + b[i]) of these points, one row per edge.
    for (std::size_t q = 0; q < points; ++q) {
      const std::size_t i = first + q;
      const float* centre = e.b + i * e.ld_ab;
      for (std::size_t j = 0; j < k; ++j) {
        const float* neighbour = e.a + static_cast<std::size_t>(e.idx[i * k + j]) * e.ld_ab;
        float* row = edges + (q * k + j) * hidden;
        std::size_t c = 0;
        for (; c < hidden_vec; c += L) {
          const B v = B::load_unaligned(neighbour + c) + B::load_unaligned(centre + c);
          leaky<Arch>(v, slope1).store_unaligned(row + c);
        }
        for (; c < hidden; ++c) {
          const float v = neighbour[c] + centre[c];
          row[c] = v >= 0.0f ? v : e.slope1 * v;
        }
      }
    }
    for (std::size_t c = 0; c < points * width; ++c) maxima[c] = -std::numeric_limits<float>::infinity();
    // Second convolution over all edge rows, reduced to a max per point.
    const std::size_t rows_total = points * k;
    for (std::size_t p = 0; p < w.panel_count(); ++p) {
      const float* panel = w.panel(p);
      for (std::size_t row = 0; row < rows_total; row += MR) {
        const int rows = static_cast<int>(min_size(MR, rows_total - row));
        with_rows<MR>(rows, [&](auto rc) {
          constexpr int R = decltype(rc)::value;
          B acc[R][2];
          for (int r = 0; r < R; ++r) acc[r][0] = acc[r][1] = B(0.0f);
          accumulate<Arch, R>(edges + row * hidden, hidden, panel, hidden, acc);
          // Spill with constant indices (see knn_body.hpp), then reduce.
          alignas(64) float tile[R][NR];
#pragma GCC unroll 16
          for (int r = 0; r < R; ++r) {
            acc[r][0].store_aligned(tile[r]);
            acc[r][1].store_aligned(tile[r] + L);
          }
          for (int r = 0; r < R; ++r) {
            float* m = maxima + ((row + r) / k) * width + p * NR;
            xsimd::max(B::load_aligned(m), B::load_aligned(tile[r])).store_aligned(m);
            xsimd::max(B::load_aligned(m + L), B::load_aligned(tile[r] + L)).store_aligned(m + L);
          }
        });
      }
    }
    for (std::size_t q = 0; q < points; ++q) {
      float* out = e.out + (first + q) * e.ldo;
      const float* m = maxima + q * width;
      for (std::size_t c = 0; c < w.rows(); ++c) {
        const float v = m[c] + w.bias()[c];
        out[c] = v >= 0.0f ? v : e.slope2 * v;
      }
    }
  }
}

// out[i][c] = act(max_j a[idx[i][j]][c] + b[i][c]): a single-convolution
// EdgeConv after the split, where only a gather-max is left per edge.
template <class Arch>
void gather_max_points_impl(const detail::EdgeConvArgs& e, std::size_t begin, std::size_t end) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  const std::size_t k = e.k, channels = e.hidden;
  const std::size_t vec = channels - channels % L;
  const B slope(e.slope1);
  for (std::size_t i = begin; i < end; ++i) {
    const std::uint32_t* nb = e.idx + i * k;
    const float* centre = e.b + i * e.ld_ab;
    float* out = e.out + i * e.ldo;
    std::size_t c = 0;
    for (; c < vec; c += L) {
      B m = B::load_unaligned(e.a + static_cast<std::size_t>(nb[0]) * e.ld_ab + c);
      for (std::size_t j = 1; j < k; ++j) m = xsimd::max(m, B::load_unaligned(e.a + static_cast<std::size_t>(nb[j]) * e.ld_ab + c));
      leaky<Arch>(m + B::load_unaligned(centre + c), slope).store_unaligned(out + c);
    }
    for (; c < channels; ++c) {
      float m = e.a[static_cast<std::size_t>(nb[0]) * e.ld_ab + c];
      for (std::size_t j = 1; j < k; ++j) {
        const float v = e.a[static_cast<std::size_t>(nb[j]) * e.ld_ab + c];
        m = v > m ? v : m;
      }
      const float v = m + centre[c];
      out[c] = v >= 0.0f ? v : e.slope1 * v;
    }
  }
}

}  // namespace
}  // namespace sarmap::kernels
