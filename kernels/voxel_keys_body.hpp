// voxel_keys() compiled per instruction set by voxel_keys_{avx2,avx512}.cpp:
// a vector of doubles per axis (the floats widened), floored, converted to
// 64-bit integers and packed; lanes out of limits take kRejectedVoxelKey.
// AVX2 over xsimd, AVX-512 in its own loop of intrinsics; the tail runs
// the reference.
#pragma once

#include <xsimd/xsimd.hpp>

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "kernels/voxel_keys.hpp"

namespace sarmap::kernels {
namespace {

// Four floats widened to doubles (the AVX2 loop; AVX-512 has its own).
template <class Arch>
inline xsimd::batch<double, Arch> load_widened(const float* p) {
  static_assert(std::is_base_of_v<xsimd::avx, Arch>, "load_widened: no conversion for this instruction set");
  return _mm256_cvtps_pd(_mm_loadu_ps(p));
}

// Lanes holding integers within int32 range, as 64-bit integers (AVX2 has no
// direct double-to-int64 conversion; xsimd's fallback is scalar).
template <class Arch>
inline xsimd::batch<std::int64_t, Arch> to_int64(const xsimd::batch<double, Arch>& x) {
  static_assert(std::is_base_of_v<xsimd::avx2, Arch>, "to_int64: no conversion for this instruction set");
  return _mm256_cvtepi32_epi64(_mm256_cvttpd_epi32(x));
}

// The AVX-512 loop over whole vectors of 8 points; returns the points done.
// Fewer instructions a lane than the loop below: out-of-limit lanes zeroed
// by the multiply's mask, one conversion to 64 bits (AVX512DQ), and the
// three offsets added once: each field plus its offset lies in [0, 2^21),
// so the packed key is the sum of the shifted signed indices and the
// shifted offsets.
#if defined(__AVX512F__)
inline std::size_t voxel_keys_avx512_vectors(const float* const axes[3], std::size_t count, double inv_resolution,
                                             double max_coordinate, std::uint64_t* keys) {
  const __m512d inv = _mm512_set1_pd(inv_resolution), limit = _mm512_set1_pd(max_coordinate);
  const __m512i offsets = _mm512_set1_epi64(static_cast<std::int64_t>(
      (static_cast<std::uint64_t>(kVoxelKeyOffset) << (2 * kVoxelKeyBits)) |
      (static_cast<std::uint64_t>(kVoxelKeyOffset) << kVoxelKeyBits) | static_cast<std::uint64_t>(kVoxelKeyOffset)));
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8) {
    __m512i packed = offsets;
    __mmask8 inside = 0xff;
    for (int a = 0; a < 3; ++a) {
      const __m512d c = _mm512_cvtps_pd(_mm256_loadu_ps(axes[a] + i));
      const __mmask8 axis_inside = _mm512_cmp_pd_mask(_mm512_abs_pd(c), limit, _CMP_LE_OQ);  // false for NaN
      inside &= axis_inside;
      const __m512d cell =
          _mm512_roundscale_pd(_mm512_maskz_mul_pd(axis_inside, c, inv), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
      packed = _mm512_add_epi64(packed, _mm512_slli_epi64(_mm512_cvttpd_epi64(cell), kVoxelKeyBits * a));
    }
    _mm512_storeu_si512(keys + i, _mm512_mask_mov_epi64(_mm512_set1_epi64(-1), inside, packed));
  }
  return i;
}
#endif

// The AVX2 loop over whole vectors of 4 points; returns the points done.
template <class Arch>
std::size_t voxel_keys_vectors(const float* const axes[3], std::size_t count, double inv_resolution,
                               double max_coordinate, std::uint64_t* keys) {
  using D = xsimd::batch<double, Arch>;
  using I = xsimd::batch<std::int64_t, Arch>;
  constexpr std::size_t N = D::size;
  const D inv(inv_resolution), limit(max_coordinate);
  const I offset(kVoxelKeyOffset);
  std::size_t i = 0;
  for (; i + N <= count; i += N) {
    I packed(std::int64_t{0});
    auto inside = D(0.0) == D(0.0);  // all lanes true
    for (int a = 0; a < 3; ++a) {
      const D c = load_widened<Arch>(axes[a] + i);
      const auto axis_inside = xsimd::abs(c) <= limit;  // false for NaN
      inside = inside && axis_inside;
      // Out-of-limit lanes are floored as 0 (their key is replaced below),
      // so every conversion is of an integer well within int32.
      const I index = to_int64<Arch>(xsimd::floor(xsimd::select(axis_inside, c, D(0.0)) * inv)) + offset;
      packed = packed | (index << (kVoxelKeyBits * a));
    }
    // All ones (kRejectedVoxelKey) where a lane is out of limits: -1 or 0.
    const I rejected = -to_int64<Arch>(xsimd::select(inside, D(0.0), D(1.0)));
    (packed | rejected).store_unaligned(reinterpret_cast<std::int64_t*>(keys + i));
  }
  return i;
}

template <class Arch>
void voxel_keys_impl(const float* x, const float* y, const float* z, std::size_t count, double inv_resolution,
                     double max_coordinate, std::uint64_t* keys) {
  const float* const axes[3] = {x, y, z};
  std::size_t i = 0;
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    i = voxel_keys_avx512_vectors(axes, count, inv_resolution, max_coordinate, keys);
  } else
#endif
  {
    i = voxel_keys_vectors<Arch>(axes, count, inv_resolution, max_coordinate, keys);
  }
  voxel_keys_reference(x + i, y + i, z + i, count - i, inv_resolution, max_coordinate, keys + i);
}

}  // namespace
}  // namespace sarmap::kernels
