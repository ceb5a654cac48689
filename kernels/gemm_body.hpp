// The GEMM kernels written once over the xsimd architecture and compiled per
// instruction set by gemm_{sse42,avx2,avx512}.cpp: a 1x1 convolution with its
// bias and LeakyReLU fused into the store, and a variant that keeps only the
// per-column maximum (the DGCNN global feature) so its N x emb output is never
// written.
#pragma once

#include <cstddef>

#include "kernels/gemm_args.hpp"
#include "kernels/microkernel.hpp"

namespace sarmap::kernels {
namespace {

template <class Arch>
void gemm_rows_impl(const detail::GemmArgs& g, std::size_t begin, std::size_t end) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  constexpr int MR = tile_rows<Arch>();
  const PackedMatrix& w = *g.w;
  const std::size_t depth = w.cols();
  const B slope(g.slope);
  for (std::size_t p = 0; p < w.panel_count(); ++p) {
    const float* panel = w.panel(p);
    const std::size_t col0 = p * 2 * L;
    const std::size_t valid = min_size(2 * L, w.rows() - col0);
    const B bias0 = B::load_aligned(g.bias + col0);
    const B bias1 = B::load_aligned(g.bias + col0 + L);
    for (std::size_t row = begin; row < end; row += MR) {
      const int rows = static_cast<int>(min_size(MR, end - row));
      with_rows<MR>(rows, [&](auto rc) {
        constexpr int R = decltype(rc)::value;
        B acc[R][2];
        for (int r = 0; r < R; ++r) acc[r][0] = acc[r][1] = B(0.0f);
        accumulate<Arch, R>(g.x + row * g.ldx, g.ldx, panel, depth, acc);
        for (int r = 0; r < R; ++r) {
          B v0 = acc[r][0] + bias0, v1 = acc[r][1] + bias1;
          v0 = xsimd::max(v0, v0 * slope);
          v1 = xsimd::max(v1, v1 * slope);
          float* out = g.y + (row + r) * g.ldy + col0;
          if (valid == 2 * L) {
            v0.store_unaligned(out);
            v1.store_unaligned(out + L);
          } else {
            alignas(64) float tmp[2 * L];
            v0.store_aligned(tmp);
            v1.store_aligned(tmp + L);
            for (std::size_t c = 0; c < valid; ++c) out[c] = tmp[c];
          }
        }
      });
    }
  }
}

template <class Arch>
void gemm_column_max_impl(const detail::GemmArgs& g, std::size_t begin, std::size_t end, float* colmax) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  constexpr int MR = tile_rows<Arch>();
  const PackedMatrix& w = *g.w;
  for (std::size_t p = 0; p < w.panel_count(); ++p) {
    const float* panel = w.panel(p);
    B m0 = B::load_aligned(colmax + p * 2 * L), m1 = B::load_aligned(colmax + p * 2 * L + L);
    for (std::size_t row = begin; row < end; row += MR) {
      const int rows = static_cast<int>(min_size(MR, end - row));
      with_rows<MR>(rows, [&](auto rc) {
        constexpr int R = decltype(rc)::value;
        B acc[R][2];
        for (int r = 0; r < R; ++r) acc[r][0] = acc[r][1] = B(0.0f);
        accumulate<Arch, R>(g.x + row * g.ldx, g.ldx, panel, w.cols(), acc);
        for (int r = 0; r < R; ++r) {
          m0 = xsimd::max(m0, acc[r][0]);
          m1 = xsimd::max(m1, acc[r][1]);
        }
      });
    }
    m0.store_aligned(colmax + p * 2 * L);
    m1.store_aligned(colmax + p * 2 * L + L);
  }
}

}  // namespace
}  // namespace sarmap::kernels
