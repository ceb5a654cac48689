// Coarser views of a metric map (2x, 4x, 8x voxels), computed on demand as
// the multi-resolution semantic OctoMap does: a coarse voxel takes its
// children's maximum log-odds (occupied if any child is occupied, free if all
// known children are free) and the class with the most evidence summed over
// its occupied children. A factor divides the 8-voxel block, so a coarse
// voxel never spans two blocks.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

struct CoarseVoxel {
  VoxelKey key;  // in coarse voxel units
  VoxelState state = VoxelState::Unknown;
  std::int16_t log_odds = kUnknownLogOdds;  // maximum over known children
  ClassId class_id = ClassId::Unknown;
  std::array<std::int32_t, kClassCount> evidence{};  // summed over occupied children
};

class CoarseView {
 public:
  // factor is 2, 4 or 8; anything else throws sarmap::Error (InvalidArgument).
  CoarseView(const MetricMap& map, int factor);

  int factor() const { return factor_; }
  double resolution() const { return map_->resolution() * factor_; }

  CoarseVoxel voxel(const VoxelKey& coarse_key) const;
  CoarseVoxel voxel_at(const Eigen::Vector3d& point) const;
  // Every known coarse voxel, in block order.
  std::vector<CoarseVoxel> known_voxels() const;

 private:
  const MetricMap* map_;
  int factor_;
  int shift_;
};

}  // namespace sarmap::metric
