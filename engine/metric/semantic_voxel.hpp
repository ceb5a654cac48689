// What the metric map knows of a voxel: quantised occupancy log-odds and
// evidence for every one of the six classes (no top-k approximation). The
// map stores it compactly, a byte per value (semantic_block.hpp); a
// SemanticVoxel is the value read from or written to one voxel, and a
// block's 512 of them in a row (DenseVoxels) are what checkpoints hold.
#pragma once

#include <array>
#include <cstdint>
#include <limits>

#include "engine/core/classes.hpp"
#include "engine/metric/voxel_key.hpp"

namespace sarmap::metric {

// Occupancy log-odds are int16 fixed point: 1 unit = 1/32 nat. The map stores
// them in one byte (semantic_block.hpp), so every known value lies within
// +-kMaxStoredLogOdds (+-3.97 nats, probabilities 0.019 to 0.981): OctoMap's
// clamp range [-1.99, 3.48] takes -64 to 111, a hit (0.847) is 27 units and a
// miss (-0.405) -13. OccupancyModel refuses settings that do not fit.
inline constexpr double kLogOddsScale = 32.0;
inline constexpr int kMaxStoredLogOdds = 127;
// The value no update produces: a voxel never observed.
inline constexpr std::int16_t kUnknownLogOdds = std::numeric_limits<std::int16_t>::min();

// A log-odds value in its one stored byte, and back (unknown is -128). Only
// values within +-kMaxStoredLogOdds (or unknown) survive the round trip.
inline constexpr std::int8_t kStoredUnknownLogOdds = std::numeric_limits<std::int8_t>::min();
inline std::int8_t stored_log_odds(std::int16_t log_odds) {
  return log_odds == kUnknownLogOdds ? kStoredUnknownLogOdds : static_cast<std::int8_t>(log_odds);
}
inline std::int16_t log_odds_of(std::int8_t stored) {
  return stored == kStoredUnknownLogOdds ? kUnknownLogOdds : std::int16_t{stored};
}
inline bool storable_log_odds(std::int16_t log_odds) {
  return log_odds == kUnknownLogOdds || (log_odds >= -kMaxStoredLogOdds && log_odds <= kMaxStoredLogOdds);
}

enum class VoxelState : std::uint8_t { Unknown = 0, Free = 1, Occupied = 2 };

struct SemanticVoxel {
  std::int16_t log_odds = kUnknownLogOdds;
  // Per-class evidence; its meaning (point counts or Bayesian log-odds against
  // class 0) depends on the map's ClassFusion.
  std::array<std::int16_t, kClassCount> evidence{};

  bool known() const { return log_odds != kUnknownLogOdds; }
};
static_assert(sizeof(SemanticVoxel) == 14);

// A block's voxels in local index order (x + 8y + 64z).
using DenseVoxels = std::array<SemanticVoxel, kBlockVoxels>;

}  // namespace sarmap::metric
