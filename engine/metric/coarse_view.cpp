#include "engine/metric/coarse_view.hpp"

#include <algorithm>

#include "engine/core/error.hpp"

namespace sarmap::metric {

CoarseView::CoarseView(const MetricMap& map, int factor) : map_(&map), factor_(factor) {
  if (factor != 2 && factor != 4 && factor != 8) {
    throw Error(ErrorCode::InvalidArgument, "coarse view: factor must be 2, 4 or 8, got " + std::to_string(factor));
  }
  shift_ = factor == 2 ? 1 : (factor == 4 ? 2 : 3);
}

namespace {
CoarseVoxel combine(const MetricMap& map, const MetricMap::Blocks::Block& block, const VoxelKey& coarse,
                    int factor, int shift) {
  CoarseVoxel out;
  out.key = coarse;
  const OccupancyModel& occ = map.occupancy();
  for (int dz = 0; dz < factor; ++dz)
    for (int dy = 0; dy < factor; ++dy)
      for (int dx = 0; dx < factor; ++dx) {
        const VoxelKey child{(coarse.x << shift) + dx, (coarse.y << shift) + dy, (coarse.z << shift) + dz};
        const SemanticVoxel v = block.voxel(local_index(child));
        if (!v.known()) continue;
        if (out.log_odds == kUnknownLogOdds || v.log_odds > out.log_odds) out.log_odds = v.log_odds;
        if (occ.state(v.log_odds) == VoxelState::Occupied) {
          for (std::size_t c = 0; c < kClassCount; ++c) out.evidence[c] += v.evidence[c];
        }
      }
  out.state = occ.state(out.log_odds);
  if (out.state == VoxelState::Occupied) {
    const auto best = std::max_element(out.evidence.begin(), out.evidence.end());  // first max: lowest id
    out.class_id = static_cast<ClassId>(best - out.evidence.begin());
  }
  return out;
}
}  // namespace

CoarseVoxel CoarseView::voxel(const VoxelKey& coarse) const {
  const VoxelKey first{coarse.x * factor_, coarse.y * factor_, coarse.z * factor_};
  const auto* block = map_->blocks().find(block_of(first));
  if (!block) {
    CoarseVoxel out;
    out.key = coarse;
    return out;
  }
  return combine(*map_, *block, coarse, factor_, shift_);
}

CoarseVoxel CoarseView::voxel_at(const Eigen::Vector3d& point) const {
  const auto key = map_->key_at(point);
  if (!key) return CoarseVoxel{};
  return voxel({key->x >> shift_, key->y >> shift_, key->z >> shift_});
}

std::vector<CoarseVoxel> CoarseView::known_voxels() const {
  std::vector<CoarseVoxel> out;
  const int per_edge = kBlockEdge / factor_;
  for (const BlockKey& bk : map_->blocks().sorted_block_keys()) {
    const auto& block = *map_->blocks().find(bk);
    for (int z = 0; z < per_edge; ++z)
      for (int y = 0; y < per_edge; ++y)
        for (int x = 0; x < per_edge; ++x) {
          const VoxelKey coarse{bk.x * per_edge + x, bk.y * per_edge + y, bk.z * per_edge + z};
          CoarseVoxel v = combine(*map_, block, coarse, factor_, shift_);
          if (v.state != VoxelState::Unknown) out.push_back(v);
        }
  }
  return out;
}

}  // namespace sarmap::metric
