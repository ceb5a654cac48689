// The log-odds miss kernel for AVX-512 (flags in kernels/CMakeLists.txt): a
// word of mask bits is the byte mask of 64 voxels, so a word takes one
// masked update with no mask to build.
#include <immintrin.h>

#include "kernels/log_odds_misses.hpp"

namespace sarmap::kernels::detail {

void apply_log_odds_misses_avx512(std::int8_t* log_odds, const std::uint64_t* misses,
                                  const LogOddsMiss& update, std::uint64_t* free_after) {
  const __m512i unknown = _mm512_set1_epi8(kUnknownLogOddsByte);
  const __m512i miss = _mm512_set1_epi8(static_cast<char>(update.miss));
  const __m512i lowest = _mm512_set1_epi8(static_cast<char>(update.lowest));
  const __m512i highest = _mm512_set1_epi8(static_cast<char>(update.highest));
  const __m512i threshold = _mm512_set1_epi8(static_cast<char>(update.threshold));
  for (int w = 0; w < kLogOddsBlockWords; ++w) {
    const __mmask64 selected = misses[w];
    if (selected == 0) {
      free_after[w] = 0;
      continue;
    }
    std::int8_t* const at = log_odds + w * 64;
    const __m512i v = _mm512_loadu_si512(at);
    const __m512i base = _mm512_mask_mov_epi8(v, _mm512_cmpeq_epi8_mask(v, unknown), _mm512_setzero_si512());
    // Saturating, as in the SSE4.2 version.
    const __m512i after = _mm512_min_epi8(_mm512_max_epi8(_mm512_adds_epi8(base, miss), lowest), highest);
    _mm512_mask_storeu_epi8(at, selected, after);
    free_after[w] = _mm512_mask_cmplt_epi8_mask(selected, after, threshold);
  }
}

}  // namespace sarmap::kernels::detail
