// A kNN row's first panel, taken at once: its candidate keys (see
// knn_candidate_list.hpp) built across the vector lanes and sorted by a
// bitonic network into the row's still empty list. The first panel a tile
// visits is its own, where every lane passes (the list is not full yet), and
// inserting its lanes one at a time made many of the 64-d kernel's
// insertions, each waiting on the one before; the network needs fewer
// instructions and has no such chain. AVX2 and AVX-512 only (a panel
// is 16 or 32 keys, four vectors of either); SSE4.2 inserts one at a time.
// Included only by the per-instruction-set kNN files (internal linkage, see
// microkernel.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "kernels/knn_candidate_list.hpp"

namespace sarmap::kernels {
namespace {

// Whether Arch has panel_keys_sorted() (below).
template <class Arch>
constexpr bool has_panel_sort() {
  return std::is_base_of_v<xsimd::avx2, Arch> || std::is_base_of_v<xsimd::avx512f, Arch>;
}

// Keys whose rank is +inf or more (as keyed by candidate_key()) or NaN:
// the lanes that may not enter a list.
inline constexpr std::int64_t kExcludedKeyFloor = std::int64_t{0x7f800000} << 32;

// Whether element `lane` of a bitonic sort's compare-exchange at distance
// `distance` within runs of `run` elements receives the larger key: the upper
// element of each pair in an ascending run, the lower in a descending one
// (runs alternate; the last, of every element, is ascending).
constexpr bool takes_larger(int lane, int run, int distance) {
  return ((lane & distance) != 0) != ((lane & run) != 0);
}

// The compare-exchange pieces per vector type: the smaller and the larger
// key of each lane pair, and one in-vector stage (each lane against the lane
// `Distance` away) for the keys first_key .. of one vector.
#if defined(__AVX512F__)
// The plain forms of these intrinsics pass GCC 12's _mm512_undefined_epi32()
// as the unused merge source, which it then reports as used uninitialized;
// the zero-masking forms with every lane set are the same operations.
inline __m512i min_keys(__m512i a, __m512i b) { return _mm512_maskz_min_epi64(0xff, a, b); }
inline __m512i max_keys(__m512i a, __m512i b) { return _mm512_maskz_max_epi64(0xff, a, b); }

template <int Run, int Distance>
inline __m512i exchanged_within(__m512i v, int first_key) {
  const __m512i partner = _mm512_set_epi64(7 ^ Distance, 6 ^ Distance, 5 ^ Distance, 4 ^ Distance, 3 ^ Distance,
                                           2 ^ Distance, 1 ^ Distance, 0 ^ Distance);
  __mmask8 larger = 0;
  for (int l = 0; l < 8; ++l) larger |= takes_larger(first_key + l, Run, Distance) ? __mmask8(1u << l) : __mmask8(0);
  const __m512i other = _mm512_maskz_permutexvar_epi64(0xff, partner, v);
  return _mm512_mask_blend_epi64(larger, min_keys(v, other), max_keys(v, other));
}
#endif

#if defined(__AVX2__)
// AVX2 has no 64-bit min or max: a compare picks each lane's side (the
// compiler shares the compare between a min and a max of the same pair).
inline __m256i min_keys(__m256i a, __m256i b) { return _mm256_blendv_epi8(a, b, _mm256_cmpgt_epi64(a, b)); }
inline __m256i max_keys(__m256i a, __m256i b) { return _mm256_blendv_epi8(b, a, _mm256_cmpgt_epi64(a, b)); }

template <int Run, int Distance>
inline __m256i exchanged_within(__m256i v, int first_key) {
  constexpr int swap = Distance == 1 ? _MM_SHUFFLE(2, 3, 0, 1) : _MM_SHUFFLE(1, 0, 3, 2);
  const auto lane_mask = [first_key](int l) -> long long { return takes_larger(first_key + l, Run, Distance) ? -1 : 0; };
  const __m256i larger = _mm256_set_epi64x(lane_mask(3), lane_mask(2), lane_mask(1), lane_mask(0));
  const __m256i other = _mm256_permute4x64_epi64(v, swap);
  // A lane takes its partner's key when that one is smaller (it keeps the
  // smaller) or not (it keeps the larger).
  const __m256i take_other = _mm256_xor_si256(_mm256_cmpgt_epi64(v, other), larger);
  return _mm256_blendv_epi8(v, other, take_other);
}
#endif

// One compare-exchange stage of a bitonic sort of the keys in four vectors
// (key lanes * a + l in lane l of v[a]): between vectors when the distance
// spans whole vectors, else within each.
template <int Run, int Distance, class Vector>
inline void bitonic_stage(Vector (&v)[4]) {
  constexpr int lanes = static_cast<int>(sizeof(Vector) / sizeof(std::int64_t));
  if constexpr (Distance >= lanes) {
    constexpr int step = Distance / lanes;
#pragma GCC unroll 4
    for (int a = 0; a < 4; ++a) {
      if ((a & step) != 0) continue;
      const Vector low = min_keys(v[a], v[a + step]), high = max_keys(v[a], v[a + step]);
      const bool ascending = ((lanes * a) & Run) == 0;
      v[a] = ascending ? low : high;
      v[a + step] = ascending ? high : low;
    }
  } else {
#pragma GCC unroll 4
    for (int a = 0; a < 4; ++a) v[a] = exchanged_within<Run, Distance>(v[a], lanes * a);
  }
}

// Batcher's bitonic sort of the keys in v, ascending: runs of 2, 4, ...
// sorted alternately up and down, each pair merged into one sorted run.
template <class Vectors, int Count, int Run = 2, int Distance = 1>
inline void bitonic_sort(Vectors& v) {
  bitonic_stage<Run, Distance>(v);
  if constexpr (Distance > 1) {
    bitonic_sort<Vectors, Count, Run, Distance / 2>(v);
  } else if constexpr (Run < Count) {
    bitonic_sort<Vectors, Count, 2 * Run, Run>(v);
  }
}

// Writes into keys[0 .. chunks * keys_per_vector<Arch>()) (a list with no
// entry yet) the sorted keys of the panel's lanes set in `passing`:
// candidate_key(rank[l], id_of_lane(l)) for the 2 * Batch<Arch>::size lanes
// l. ids holds each lane's index (first_id + l when ids is null); only the
// first `lanes` entries of it are read. A list longer than the panel keeps
// its empty tail; a shorter one takes the smallest keys.
template <class Arch>
inline void panel_keys_sorted(std::int64_t* keys, std::size_t chunks, const float* rank, std::uint64_t passing,
                              const std::uint32_t* ids, std::uint32_t first_id, std::size_t lanes) {
  [[maybe_unused]] constexpr std::int64_t kNoKey = std::numeric_limits<std::int64_t>::max();  // likewise
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
    __m512i v[4];
    const __m512i iota = _mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
    for (int h = 0; h < 2; ++h) {
      const auto pass = static_cast<__mmask16>(passing >> (16 * h));
      // -0 becomes +0 as in candidate_key(); lanes that do not pass become +inf.
      const __m512 r = _mm512_mask_mov_ps(_mm512_set1_ps(std::numeric_limits<float>::infinity()), pass,
                                          _mm512_add_ps(_mm512_load_ps(rank + 16 * h), _mm512_setzero_ps()));
      __m512i bits = _mm512_castps_si512(r);
      bits = _mm512_xor_si512(bits, _mm512_and_si512(_mm512_srai_epi32(bits, 31), _mm512_set1_epi32(0x7fffffff)));
      const std::size_t first = 16 * static_cast<std::size_t>(h);
      const auto present = static_cast<__mmask16>(lanes <= first ? 0u : lanes - first >= 16 ? 0xffffu : (1u << (lanes - first)) - 1);
      const __m512i id = ids != nullptr ? _mm512_maskz_loadu_epi32(present, ids + first)
                                        : _mm512_add_epi32(_mm512_set1_epi32(static_cast<int>(first_id + first)), iota);
      // Index below the rank bits: each 64-bit lane is a key (in a lane
      // order the sort makes irrelevant).
      v[2 * h] = _mm512_unpacklo_epi32(id, bits);
      v[2 * h + 1] = _mm512_unpackhi_epi32(id, bits);
    }
    bitonic_sort<__m512i[4], 32>(v);
    const __m512i excluded_floor = _mm512_set1_epi64(kExcludedKeyFloor), no_key = _mm512_set1_epi64(kNoKey);
    for (std::size_t c = 0; c < 4 && c < chunks; ++c) {
      _mm512_store_si512(keys + 8 * c, _mm512_mask_mov_epi64(v[c], _mm512_cmpge_epi64_mask(v[c], excluded_floor), no_key));
    }
    return;
  } else
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of_v<xsimd::avx2, Arch>) {
    __m256i v[4];
    const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    const __m256i lane_bit = _mm256_set_epi32(128, 64, 32, 16, 8, 4, 2, 1);
    const __m256i iota = _mm256_set_epi32(7, 6, 5, 4, 3, 2, 1, 0);
    for (int h = 0; h < 2; ++h) {
      const __m256i pass_bits = _mm256_set1_epi32(static_cast<int>((passing >> (8 * h)) & 0xffu));
      const __m256 pass = _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(pass_bits, lane_bit), lane_bit));
      const __m256 r = _mm256_blendv_ps(inf, _mm256_add_ps(_mm256_load_ps(rank + 8 * h), _mm256_setzero_ps()), pass);
      __m256i bits = _mm256_castps_si256(r);
      bits = _mm256_xor_si256(bits, _mm256_and_si256(_mm256_srai_epi32(bits, 31), _mm256_set1_epi32(0x7fffffff)));
      const std::size_t first = 8 * static_cast<std::size_t>(h);
      __m256i id;
      if (ids == nullptr) {
        id = _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(first_id + first)), iota);
      } else if (lanes >= first + 8) {
        id = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ids + first));
      } else {
        const __m256i present = _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>(lanes) - static_cast<int>(first)), iota);
        id = _mm256_maskload_epi32(reinterpret_cast<const int*>(ids + first), present);
      }
      v[2 * h] = _mm256_unpacklo_epi32(id, bits);
      v[2 * h + 1] = _mm256_unpackhi_epi32(id, bits);
    }
    bitonic_sort<__m256i[4], 16>(v);
    const __m256i below_excluded = _mm256_set1_epi64x(kExcludedKeyFloor - 1), no_key = _mm256_set1_epi64x(kNoKey);
    for (std::size_t c = 0; c < 4 && c < chunks; ++c) {
      const __m256i clean = _mm256_blendv_epi8(v[c], no_key, _mm256_cmpgt_epi64(v[c], below_excluded));
      _mm256_store_si256(reinterpret_cast<__m256i*>(keys + 4 * c), clean);
    }
    return;
  } else
#endif
  {
    static_assert(!has_panel_sort<Arch>(), "panel_keys_sorted: no code for this instruction set");
    // Unused where no branch above is compiled in (a build without AVX2).
    (void)keys, (void)chunks, (void)rank, (void)passing, (void)ids, (void)first_id, (void)lanes;
  }
}

}  // namespace
}  // namespace sarmap::kernels
