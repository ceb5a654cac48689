// What the metric map knows of a voxel: quantised occupancy log-odds and
// evidence for every one of the six classes (no top-k approximation). The
// map stores it compactly (semantic_block.hpp); a SemanticVoxel is the value
// read from or written to one voxel, and a block's 512 of them in a row
// (DenseVoxels, 14 bytes each) are what the .sarmap file and checkpoints hold.
#pragma once

#include <array>
#include <cstdint>
#include <limits>

#include "engine/core/classes.hpp"
#include "engine/metric/voxel_key.hpp"

namespace sarmap::metric {

// Occupancy log-odds are stored as int16 fixed point: 1 unit = 1/1024 nat, so
// OctoMap's clamp range [-1.99, 3.48] uses about +-3600 of the +-32767 available
// and a hit (0.847) or miss (-0.405) is exact to 1e-3.
inline constexpr double kLogOddsScale = 1024.0;
// The value no update produces: a voxel never observed.
inline constexpr std::int16_t kUnknownLogOdds = std::numeric_limits<std::int16_t>::min();

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
