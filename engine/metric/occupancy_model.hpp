// OctoMap's occupancy update in sarmap's fixed-point log-odds: the settings are
// probabilities (OctoMap's defaults), the model holds their quantised log-odds.
#pragma once

#include <algorithm>
#include <cstdint>

#include "engine/metric/semantic_voxel.hpp"

namespace sarmap::metric {

struct OccupancySettings {
  double prob_hit = 0.7;
  double prob_miss = 0.4;
  double clamp_min = 0.12;
  double clamp_max = 0.97;
  // A voxel is occupied when its probability is at least this (OctoMap's
  // isNodeOccupied uses >=, and so does sarmap, so the two agree on ties).
  double occupied_threshold = 0.5;
};

class OccupancyModel {
 public:
  // Throws sarmap::Error (InvalidArgument) unless
  // 0 < clamp_min <= prob_miss < 0.5 < prob_hit <= clamp_max < 1 and the threshold is in (0, 1).
  explicit OccupancyModel(const OccupancySettings& settings = {});

  const OccupancySettings& settings() const { return settings_; }
  std::int16_t hit() const { return hit_; }
  std::int16_t miss() const { return miss_; }
  std::int16_t min() const { return min_; }
  std::int16_t max() const { return max_; }
  std::int16_t threshold() const { return threshold_; }

  // An unknown voxel starts from log-odds 0 (probability 0.5), as in OctoMap.
  std::int16_t add(std::int16_t log_odds, std::int16_t delta) const {
    const int base = log_odds == kUnknownLogOdds ? 0 : log_odds;
    return static_cast<std::int16_t>(std::clamp(base + delta, int{min_}, int{max_}));
  }
  VoxelState state(std::int16_t log_odds) const {
    if (log_odds == kUnknownLogOdds) return VoxelState::Unknown;
    return log_odds >= threshold_ ? VoxelState::Occupied : VoxelState::Free;
  }
  // Probability of a known voxel (0.5 for unknown).
  static double probability(std::int16_t log_odds);
  static std::int16_t quantise(double probability);

 private:
  OccupancySettings settings_;
  std::int16_t hit_, miss_, min_, max_, threshold_;
};

}  // namespace sarmap::metric
