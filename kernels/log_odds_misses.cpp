#include "kernels/log_odds_misses.hpp"

#include <smmintrin.h>

#include <algorithm>
#include <stdexcept>

namespace sarmap::kernels {

void apply_log_odds_misses_reference(std::int8_t* log_odds, const std::uint64_t* misses,
                                     const LogOddsMiss& update, std::uint64_t* free_after) {
  for (int w = 0; w < kLogOddsBlockWords; ++w) {
    free_after[w] = 0;
    for (int bit = 0; bit < 64; ++bit) {
      if (((misses[w] >> bit) & 1u) == 0) continue;
      std::int8_t& v = log_odds[w * 64 + bit];
      const int base = v == kUnknownLogOddsByte ? 0 : v;
      const int after = std::min(std::max(base + update.miss, update.lowest), update.highest);
      v = static_cast<std::int8_t>(after);
      if (after < update.threshold) free_after[w] |= std::uint64_t{1} << bit;
    }
  }
}

namespace detail {

void apply_log_odds_misses_sse42(std::int8_t* log_odds, const std::uint64_t* misses,
                                 const LogOddsMiss& update, std::uint64_t* free_after) {
  // Byte i of a 16-voxel group takes bit i of its 16 mask bits: the two
  // mask bytes spread over the halves, then each byte tested for its bit.
  const __m128i spread = _mm_setr_epi8(0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1);
  const __m128i bit_of_byte = _mm_setr_epi8(1, 2, 4, 8, 16, 32, 64, -128, 1, 2, 4, 8, 16, 32, 64, -128);
  const __m128i unknown = _mm_set1_epi8(kUnknownLogOddsByte);
  const __m128i miss = _mm_set1_epi8(static_cast<char>(update.miss));
  const __m128i lowest = _mm_set1_epi8(static_cast<char>(update.lowest));
  const __m128i highest = _mm_set1_epi8(static_cast<char>(update.highest));
  const __m128i threshold = _mm_set1_epi8(static_cast<char>(update.threshold));
  for (int w = 0; w < kLogOddsBlockWords; ++w) {
    std::uint64_t free_bits = 0;
    for (int part = 0; part < 4; ++part) {
      const auto bits = static_cast<std::uint16_t>(misses[w] >> (16 * part));
      if (bits == 0) continue;  // most groups of a block hold few misses or none
      std::int8_t* const at = log_odds + w * 64 + part * 16;
      const __m128i selected = _mm_cmpeq_epi8(
          _mm_and_si128(_mm_shuffle_epi8(_mm_set1_epi16(static_cast<short>(bits)), spread), bit_of_byte),
          bit_of_byte);
      const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(at));
      const __m128i base = _mm_andnot_si128(_mm_cmpeq_epi8(v, unknown), v);
      // A saturating add: a sum beyond a byte saturates beyond the bounds,
      // which then clamp it as they would the exact sum.
      const __m128i after = _mm_min_epi8(_mm_max_epi8(_mm_adds_epi8(base, miss), lowest), highest);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(at), _mm_blendv_epi8(v, after, selected));
      const auto free =
          static_cast<unsigned>(_mm_movemask_epi8(_mm_and_si128(selected, _mm_cmpgt_epi8(threshold, after))));
      free_bits |= std::uint64_t{free} << (16 * part);
    }
    free_after[w] = free_bits;
  }
}

}  // namespace detail

void apply_log_odds_misses(std::int8_t* log_odds, const std::uint64_t* misses, const LogOddsMiss& update,
                           std::uint64_t* free_after, SimdLevel level) {
  if (!simd_level_supported(level))
    throw std::invalid_argument("apply_log_odds_misses: instruction set not supported");
  if (level == SimdLevel::Avx512) {
    detail::apply_log_odds_misses_avx512(log_odds, misses, update, free_after);
    return;
  }
  detail::apply_log_odds_misses_sse42(log_odds, misses, update, free_after);
}

}  // namespace sarmap::kernels
