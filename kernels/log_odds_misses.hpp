// A miss on the voxels of one 8 x 8 x 8 block whose occupancy log-odds are
// stored a byte each: the free-space update of ray integration (its pass
// 4) for every voxel a scan's rays crossed, vectorised because it runs once
// per such voxel and, one voxel at a time, was a large part of the pass. For
// each voxel l whose bit is set in misses[l / 64] (bit l % 64), its value v
// (0 for kUnknownLogOddsByte, a voxel never observed, as OctoMap starts it)
// becomes min(max(v + miss, lowest), highest); free_after[l / 64] gets the
// bit of every such voxel whose new value is below threshold (a free
// voxel), and no other. Voxels without their bit are left as they are. The
// vector versions compute exactly the reference's bytes and bits.
#pragma once

#include <cstdint>

#include "kernels/simd_level.hpp"

namespace sarmap::kernels {

inline constexpr int kLogOddsBlockVoxels = 512;
inline constexpr int kLogOddsBlockWords = kLogOddsBlockVoxels / 64;
inline constexpr std::int8_t kUnknownLogOddsByte = -128;

// The values' bounds: lowest <= highest within +-127, miss and threshold
// within +-127 (they are the map's occupancy model's, OccupancyModel).
struct LogOddsMiss {
  int miss, lowest, highest, threshold;
};

void apply_log_odds_misses(std::int8_t* log_odds, const std::uint64_t* misses, const LogOddsMiss& update,
                           std::uint64_t* free_after, SimdLevel level);

// One voxel at a time: the definition.
void apply_log_odds_misses_reference(std::int8_t* log_odds, const std::uint64_t* misses,
                                     const LogOddsMiss& update, std::uint64_t* free_after);

namespace detail {
// Sixteen voxels per step (SSE4.2, the baseline; the AVX2 level uses it too).
void apply_log_odds_misses_sse42(std::int8_t* log_odds, const std::uint64_t* misses,
                                 const LogOddsMiss& update, std::uint64_t* free_after);
// A word of 64 voxels per step, its bits the byte mask.
void apply_log_odds_misses_avx512(std::int8_t* log_odds, const std::uint64_t* misses,
                                  const LogOddsMiss& update, std::uint64_t* free_after);
}  // namespace detail

}  // namespace sarmap::kernels
