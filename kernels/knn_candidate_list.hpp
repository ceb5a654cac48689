// A kNN row's candidate list: its best (rank, index) pairs in ascending
// order, each pair one 64-bit integer key, so that one signed 64-bit compare
// orders by rank and, among equal ranks, by index. Ordering equal ranks by
// index, not by arrival, keeps the candidates independent of the visiting
// order: of many equal points (a block padded by repeats) the smallest
// indices stay. Included only by the per-instruction-set kNN files (see
// microkernel.hpp for why everything here has internal linkage).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace sarmap::kernels {
namespace {

// The key of (rank, index): the rank's float bits made monotone as a signed
// 32-bit integer (negative floats' magnitude bits reversed) above the index.
inline std::int64_t candidate_key(float rank, std::uint32_t id) {
  rank += 0.0f;  // -0 becomes +0: the two compare equal as floats, so they must tie here too
  std::int32_t bits;
  std::memcpy(&bits, &rank, sizeof bits);
  bits ^= (bits >> 31) & 0x7fffffff;
  return static_cast<std::int64_t>((static_cast<std::uint64_t>(static_cast<std::uint32_t>(bits)) << 32) | id);
}

inline float rank_of_key(std::int64_t key) {
  auto bits = static_cast<std::int32_t>(key >> 32);
  bits ^= (bits >> 31) & 0x7fffffff;
  float rank;
  std::memcpy(&rank, &bits, sizeof rank);
  return rank;
}

inline std::uint32_t index_of_key(std::int64_t key) { return static_cast<std::uint32_t>(key); }

// Keys per vector of the instruction set Arch.
template <class Arch>
constexpr std::size_t keys_per_vector() {
  return Arch::alignment() / sizeof(std::int64_t);
}

// One vector of an insertion of xv: `cur` with xv placed and the entries
// above it shifted up a lane, `below` being the (unshifted) vector before it.
// Shared by insert_candidate() and insert_candidates_in_registers().
#if defined(__AVX512F__)
inline __m512i inserted_vector(__m512i cur, __m512i below, __m512i xv) {
  const __m512i prev = _mm512_alignr_epi64(cur, below, 7);
  const __m512i placed = _mm512_mask_blend_epi64(_mm512_cmpgt_epi64_mask(cur, xv), cur, xv);
  return _mm512_mask_blend_epi64(_mm512_cmpgt_epi64_mask(prev, xv), placed, prev);
}
#endif
#if defined(__AVX2__)
inline __m256i inserted_vector(__m256i cur, __m256i below, __m256i xv) {
  // [below[3], cur[0], cur[1], cur[2]]
  const __m256i prev = _mm256_blend_epi32(_mm256_permute4x64_epi64(cur, _MM_SHUFFLE(2, 1, 0, 3)),
                                          _mm256_permute4x64_epi64(below, _MM_SHUFFLE(2, 1, 0, 3)), 0x03);
  const __m256i placed = _mm256_blendv_epi8(cur, xv, _mm256_cmpgt_epi64(cur, xv));
  return _mm256_blendv_epi8(placed, prev, _mm256_cmpgt_epi64(prev, xv));
}
#endif

// Inserts key x into the ascending list keys[0 .. chunks * keys_per_vector),
// shifting the entries after it up a slot; the last falls off. keys[-KL .. -1]
// must be a whole vector of the smallest key (a sentinel). Branch-free, a
// vector at a time from the top down, so each vector reads its unshifted
// predecessor; the predecessor lanes come from a lane shift in registers,
// because an unaligned load across the two vectors the previous insertion just
// stored stalls on store forwarding.
template <class Arch>
inline void insert_candidate(std::int64_t* keys, std::size_t chunks, std::int64_t x) {
  constexpr std::size_t KL = keys_per_vector<Arch>();
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    const __m512i xv = _mm512_set1_epi64(x);
    for (std::size_t c = chunks; c-- > 0;) {
      std::int64_t* kc = keys + c * KL;
      _mm512_store_si512(kc, inserted_vector(_mm512_load_si512(kc), _mm512_load_si512(kc - KL), xv));
    }
    return;
  } else
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of_v<xsimd::avx2, Arch>) {
    const __m256i xv = _mm256_set1_epi64x(x);
    for (std::size_t c = chunks; c-- > 0;) {
      std::int64_t* kc = keys + c * KL;
      const __m256i cur = _mm256_load_si256(reinterpret_cast<const __m256i*>(kc));
      const __m256i below = _mm256_load_si256(reinterpret_cast<const __m256i*>(kc - KL));
      _mm256_store_si256(reinterpret_cast<__m256i*>(kc), inserted_vector(cur, below, xv));
    }
    return;
  } else
#endif
  {
    static_assert(std::is_base_of_v<xsimd::sse4_2, Arch>, "insert_candidate: no code for this instruction set");
    const __m128i xv = _mm_set1_epi64x(x);
    for (std::size_t c = chunks; c-- > 0;) {
      std::int64_t* kc = keys + c * KL;
      const __m128i cur = _mm_load_si128(reinterpret_cast<const __m128i*>(kc));
      const __m128i prev = _mm_alignr_epi8(cur, _mm_load_si128(reinterpret_cast<const __m128i*>(kc - KL)), 8);
      const __m128i placed = _mm_blendv_epi8(cur, xv, _mm_cmpgt_epi64(cur, xv));
      _mm_store_si128(reinterpret_cast<__m128i*>(kc), _mm_blendv_epi8(placed, prev, _mm_cmpgt_epi64(prev, xv)));
    }
  }
}

// The largest list, in vectors, that insert_candidates_in_registers() keeps
// in registers for Arch (0: none; insert_candidate() a key at a time then).
template <class Arch>
constexpr std::size_t max_register_chunks() {
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    return 9;  // k 64 + 8 extra; 9 of 32 zmm
  } else if constexpr (std::is_base_of_v<xsimd::avx2, Arch>) {
    return 8;  // 8 of 16 ymm, leaving room for the temporaries
  } else {
    return 0;
  }
}

// Inserts the keys key_of(l) for each set bit l of `lanes`, lowest first,
// into the list keys[0 .. Chunks * keys_per_vector) (ascending; see
// insert_candidate), holding the list in registers for the whole batch:
// a key at a time through memory made each insertion wait for the previous
// one's stores. keys[-KL .. -1] is not read: the vector below the first is
// the smallest key. A key no smaller than the list's last entry changes
// nothing that is read (it may only fill a slot past the caller's `keep`,
// which the caller never reads), so the caller need not test it first.
template <class Arch, std::size_t Chunks, class KeyOf>
inline void insert_candidates_in_registers(std::int64_t* keys, std::uint64_t lanes, KeyOf key_of) {
  [[maybe_unused]] constexpr std::size_t KL = keys_per_vector<Arch>();  // unused where no branch below is compiled in
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    __m512i v[Chunks];
    for (std::size_t c = 0; c < Chunks; ++c) v[c] = _mm512_load_si512(keys + c * KL);
    const __m512i smallest = _mm512_set1_epi64(std::numeric_limits<std::int64_t>::min());
    while (lanes != 0) {
      const auto l = static_cast<std::size_t>(__builtin_ctzll(lanes));
      lanes &= lanes - 1;
      const __m512i xv = _mm512_set1_epi64(key_of(l));
#pragma GCC unroll 16
      for (std::size_t i = 0; i < Chunks; ++i) {
        const std::size_t c = Chunks - 1 - i;  // top down: each vector reads its predecessor unshifted
        v[c] = inserted_vector(v[c], c > 0 ? v[c - 1] : smallest, xv);
      }
    }
    for (std::size_t c = 0; c < Chunks; ++c) _mm512_store_si512(keys + c * KL, v[c]);
    return;
  } else
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of_v<xsimd::avx2, Arch>) {
    __m256i v[Chunks];
    for (std::size_t c = 0; c < Chunks; ++c) v[c] = _mm256_load_si256(reinterpret_cast<const __m256i*>(keys + c * KL));
    const __m256i smallest = _mm256_set1_epi64x(std::numeric_limits<std::int64_t>::min());
    while (lanes != 0) {
      const auto l = static_cast<std::size_t>(__builtin_ctzll(lanes));
      lanes &= lanes - 1;
      const __m256i xv = _mm256_set1_epi64x(key_of(l));
#pragma GCC unroll 16
      for (std::size_t i = 0; i < Chunks; ++i) {
        const std::size_t c = Chunks - 1 - i;  // top down: each vector reads its predecessor unshifted
        v[c] = inserted_vector(v[c], c > 0 ? v[c - 1] : smallest, xv);
      }
    }
    for (std::size_t c = 0; c < Chunks; ++c) _mm256_store_si256(reinterpret_cast<__m256i*>(keys + c * KL), v[c]);
    return;
  } else
#endif
  {
    static_assert(Chunks == 0, "insert_candidates_in_registers: no code for this instruction set");
    (void)keys, (void)lanes, (void)key_of;  // unused where no branch above is compiled in
  }
}

}  // namespace
}  // namespace sarmap::kernels
