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
  const SemanticVoxel* v = blocks_.voxel(key);
  return v ? occupancy_.state(v->log_odds) : VoxelState::Unknown;
}

VoxelState MetricMap::state_at(const Eigen::Vector3d& point) const {
  const auto key = key_at(point);
  return key ? state(*key) : VoxelState::Unknown;
}

double MetricMap::probability_at(const Eigen::Vector3d& point) const {
  const auto key = key_at(point);
  const SemanticVoxel* v = key ? blocks_.voxel(*key) : nullptr;
  return v ? OccupancyModel::probability(v->log_odds) : 0.5;
}

ClassId MetricMap::class_of(const VoxelKey& key) const {
  const SemanticVoxel* v = blocks_.voxel(key);
  if (!v || occupancy_.state(v->log_odds) != VoxelState::Occupied) return ClassId::Unknown;
  return LabelFusion::dominant(v->evidence);
}

ClassId MetricMap::class_at(const Eigen::Vector3d& point) const {
  const auto key = key_at(point);
  return key ? class_of(*key) : ClassId::Unknown;
}

bool MetricMap::replace_evidence(const VoxelKey& key, const ClassObservation& observation) {
  Blocks::Block* block = blocks_.find(block_of(key));
  if (block == nullptr) return false;
  SemanticVoxel& voxel = block->voxels[local_index(key)];
  if (!voxel.known()) return false;
  voxel.evidence = {};
  fusion_.observe(voxel.evidence, observation);
  return true;
}

ClassEvidence MetricMap::evidence(const VoxelKey& key) const {
  const SemanticVoxel* v = blocks_.voxel(key);
  return v ? v->evidence : ClassEvidence{};
}

MapCounts MetricMap::counts() const {
  MapCounts c;
  c.blocks = blocks_.block_count();
  blocks_.for_each_block([&](const BlockKey&, const Blocks::Block& block) {
    for (const SemanticVoxel& v : block.voxels) {
      switch (occupancy_.state(v.log_odds)) {
        case VoxelState::Free: ++c.free; break;
        case VoxelState::Occupied: ++c.occupied; break;
        case VoxelState::Unknown: break;
      }
    }
  });
  c.known = c.free + c.occupied;
  return c;
}

}  // namespace sarmap::metric
