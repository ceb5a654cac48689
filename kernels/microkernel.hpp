// The register-tiled inner loop shared by the GEMM, EdgeConv and kNN kernels:
// R rows of A times one packed panel (two vectors wide), accumulated in
// registers. Included only by the per-instruction-set .cpp files, which are
// compiled with their own -m flags; everything here has internal linkage so
// no wide-instruction code can be picked by the linker for baseline callers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace sarmap::kernels {
namespace {

template <class Arch>
using Batch = xsimd::batch<float, Arch>;

// Rows per register tile: enough accumulators to hide FMA latency, few enough
// to leave registers for the panel vectors and the broadcast.
template <class Arch>
constexpr int tile_rows() {
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    return 12;  // 24 accumulators of 32 zmm
  } else {
    return 6;  // 12 accumulators of 16 ymm / xmm
  }
}

template <class Arch>
inline Batch<Arch> fmadd(const Batch<Arch>& a, const Batch<Arch>& b, const Batch<Arch>& c) {
#if defined(__AVX512F__)
  // xsimd 8.1 has no fused multiply-add for avx512 (it emits mul + add).
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) return Batch<Arch>(_mm512_fmadd_ps(a, b, c));
#endif
  return xsimd::fma(a, b, c);
}

// acc[r][v] += sum_k a[r * lda + k] * panel[k * 2L + v * L], for k < depth.
template <class Arch, int R>
inline void accumulate(const float* a, std::size_t lda, const float* panel, std::size_t depth,
                       Batch<Arch> (&acc)[R][2]) {
  using B = Batch<Arch>;
  constexpr std::size_t L = B::size;
  for (std::size_t k = 0; k < depth; ++k) {
    const B b0 = B::load_aligned(panel + k * 2 * L);
    const B b1 = B::load_aligned(panel + k * 2 * L + L);
#pragma GCC unroll 16
    for (int r = 0; r < R; ++r) {
      const B av(a[r * lda + k]);
      acc[r][0] = fmadd<Arch>(av, b0, acc[r][0]);
      acc[r][1] = fmadd<Arch>(av, b1, acc[r][1]);
    }
  }
}

// Calls f(std::integral_constant<int, rows>) for a run-time rows in 1..R, so
// tail tiles get a fully unrolled kernel of their own height.
template <int R, class F>
inline void with_rows(int rows, F&& f) {
  if constexpr (R <= 1) {
    f(std::integral_constant<int, 1>{});
  } else {
    if (rows >= R) {
      f(std::integral_constant<int, R>{});
    } else {
      with_rows<R - 1>(rows, f);
    }
  }
}

// One bit per lane of a comparison (lane i -> bit i): lets a selection loop
// visit only the lanes that passed (xsimd 8.1 has no batch_bool::mask()).
template <class Arch>
inline std::uint32_t lane_mask(const xsimd::batch_bool<float, Arch>& b) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    return static_cast<std::uint32_t>(static_cast<__mmask16>(b));
  } else
#endif
#if defined(__AVX__)
  if constexpr (std::is_base_of_v<xsimd::avx, Arch>) {
    return static_cast<std::uint32_t>(_mm256_movemask_ps(b));
  } else
#endif
#if defined(__SSE2__)
  if constexpr (std::is_base_of_v<xsimd::sse2, Arch>) {
    return static_cast<std::uint32_t>(_mm_movemask_ps(b));
  } else
#endif
  {
    constexpr std::size_t L = Batch<Arch>::size;
    alignas(64) bool lanes[L];
    b.store_aligned(lanes);
    std::uint32_t m = 0;
    for (std::size_t i = 0; i < L; ++i) m |= static_cast<std::uint32_t>(lanes[i]) << i;
    return m;
  }
}

inline std::size_t min_size(std::size_t a, std::size_t b) { return a < b ? a : b; }

}  // namespace
}  // namespace sarmap::kernels
