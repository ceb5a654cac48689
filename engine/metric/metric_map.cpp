#include "engine/metric/metric_map.hpp"

#include <string>

#include "engine/core/error.hpp"

namespace sarmap::metric {

namespace {
double checked_resolution(double r) {
  if (!(r >= kMinResolution && r <= kMaxResolution)) {
    throw Error(ErrorCode::InvalidArgument, "metric map: resolution must be in [0.01, 100] m, got " +
                                                std::to_string(r));
  }
  return r;
}
}  // namespace

MetricMap::MetricMap(const MetricMapSettings& settings)
    : settings_(settings),
      inv_resolution_(1.0 / checked_resolution(settings.resolution)),
      occupancy_(settings.occupancy),
      fusion_(settings.fusion) {}

std::optional<VoxelKey> MetricMap::key_at(const Eigen::Vector3d& p) const {
  if (!within_map_limits(p.x(), p.y(), p.z())) return std::nullopt;
  return key_of(p.x(), p.y(), p.z(), inv_resolution_);
}

Eigen::Vector3d MetricMap::center_of(const VoxelKey& k) const {
  const double r = settings_.resolution;
  return {(k.x + 0.5) * r, (k.y + 0.5) * r, (k.z + 0.5) * r};
}

VoxelState MetricMap::state(const VoxelKey& key) const {
  const Blocks::Block* b = blocks_.find(block_of(key));
  return b ? occupancy_.state(b->log_odds(local_index(key))) : VoxelState::Unknown;
}

VoxelState MetricMap::state_at(const Eigen::Vector3d& point) const {
  const auto key = key_at(point);
  return key ? state(*key) : VoxelState::Unknown;
}

double MetricMap::probability_at(const Eigen::Vector3d& point) const {
  const auto key = key_at(point);
  const Blocks::Block* b = key ? blocks_.find(block_of(*key)) : nullptr;
  return b ? OccupancyModel::probability(b->log_odds(local_index(*key))) : 0.5;
}

ClassId MetricMap::class_of(const VoxelKey& key) const {
  const Blocks::Block* b = blocks_.find(block_of(key));
  if (!b || occupancy_.state(b->log_odds(local_index(key))) != VoxelState::Occupied) return ClassId::Unknown;
  return LabelFusion::dominant(b->evidence(local_index(key)));
}

ClassId MetricMap::class_at(const Eigen::Vector3d& point) const {
  const auto key = key_at(point);
  return key ? class_of(*key) : ClassId::Unknown;
}

bool MetricMap::replace_evidence(const VoxelKey& key, const ClassObservation& observation) {
  Blocks::Block* block = blocks_.find(block_of(key));
  if (block == nullptr) return false;
  const int l = local_index(key);
  if (!block->known(l)) return false;
  ClassEvidence evidence{};
  fusion_.observe(evidence, observation);
  blocks_.set_evidence(*block, l, evidence);
  return true;
}

ClassEvidence MetricMap::evidence(const VoxelKey& key) const {
  const Blocks::Block* b = blocks_.find(block_of(key));
  return b ? b->evidence(local_index(key)) : ClassEvidence{};
}

MapCounts MetricMap::counts() const {
  MapCounts c;
  c.blocks = blocks_.block_count();
  const auto add = [&c](VoxelState state, std::size_t n) {
    if (state == VoxelState::Free) c.free += n;
    if (state == VoxelState::Occupied) c.occupied += n;
  };
  blocks_.for_each_block([&](const BlockKey&, const Blocks::Block& block) {
    if (block.uniform_occupancy()) {
      add(occupancy_.state(block.uniform_log_odds()), kBlockVoxels);
      return;
    }
    for (int l = 0; l < kBlockVoxels; ++l) add(occupancy_.state(block.log_odds(l)), 1);
  });
  c.known = c.free + c.occupied;
  return c;
}

}  // namespace sarmap::metric
