#include "engine/metric/map_queries.hpp"

#include <cmath>

#include "engine/core/error.hpp"
#include "engine/metric/voxel_ray.hpp"

namespace sarmap::metric {

std::optional<RayHit> cast_ray(const MetricMap& map, const Eigen::Vector3d& origin,
                               const Eigen::Vector3d& direction, double max_distance) {
  const double norm = direction.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    throw Error(ErrorCode::InvalidArgument, "cast_ray: direction must be finite and non-zero");
  }
  if (!map.key_at(origin)) return std::nullopt;
  // The walk stops at the map limits, like integration.
  Eigen::Vector3d end = origin + direction / norm * std::max(0.0, max_distance);
  const double lim = kMaxCoordinate;
  end = end.cwiseMax(Eigen::Vector3d::Constant(-lim)).cwiseMin(Eigen::Vector3d::Constant(lim));
  const double inv = map.inv_resolution();
  const double start_v[3] = {origin.x() * inv, origin.y() * inv, origin.z() * inv};
  const double end_v[3] = {end.x() * inv, end.y() * inv, end.z() * inv};
  MetricMap::Blocks::ConstAccessor access(map.blocks());
  std::optional<VoxelKey> found;
  const auto occupied = [&](const VoxelKey& k) {
    const SemanticBlock* b = access.block(k);
    return b && map.occupancy().state(b->log_odds(local_index(k))) == VoxelState::Occupied;
  };
  walk_ray(start_v, end_v, [&](const VoxelKey& k) {
    if (occupied(k)) {
      found = k;
      return false;
    }
    return true;
  });
  // walk_ray stops before the end's voxel; it is inside the range too.
  if (!found) {
    const VoxelKey last = key_of(end.x(), end.y(), end.z(), inv);
    if (occupied(last)) found = last;
  }
  if (!found) return std::nullopt;
  const Eigen::Vector3d c = map.center_of(*found);
  return RayHit{*found, c, (c - origin).norm()};
}

namespace {
// Inclusive voxel range of the centres inside the box.
bool voxel_range(const MetricMap& map, const Bounds& box, VoxelKey& lo, VoxelKey& hi) {
  if (box.empty()) return false;
  const double inv = map.inv_resolution();
  const Eigen::Vector3d lim = Eigen::Vector3d::Constant(kMaxCoordinate);
  const Eigen::Vector3d a = box.min.cwiseMax(-lim), b = box.max.cwiseMin(lim);
  if ((a.array() > b.array()).any()) return false;
  // Centre (k + 0.5) r in [a, b]  <=>  k in [ceil(a/r - 0.5), floor(b/r - 0.5)].
  lo = {static_cast<std::int32_t>(std::ceil(a.x() * inv - 0.5)), static_cast<std::int32_t>(std::ceil(a.y() * inv - 0.5)),
        static_cast<std::int32_t>(std::ceil(a.z() * inv - 0.5))};
  hi = {static_cast<std::int32_t>(std::floor(b.x() * inv - 0.5)),
        static_cast<std::int32_t>(std::floor(b.y() * inv - 0.5)),
        static_cast<std::int32_t>(std::floor(b.z() * inv - 0.5))};
  return lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z;
}

template <class Fn>
void for_each_known_in_box(const MetricMap& map, const Bounds& box, Fn&& fn) {
  VoxelKey lo, hi;
  if (!voxel_range(map, box, lo, hi)) return;
  const BlockKey blo = block_of(lo), bhi = block_of(hi);
  const auto visit_block = [&](const BlockKey& bk, const MetricMap::Blocks::Block& block) {
    for (int l = 0; l < kBlockVoxels; ++l) {
      const VoxelKey k = voxel_of(bk, l);
      if (k.x < lo.x || k.y < lo.y || k.z < lo.z || k.x > hi.x || k.y > hi.y || k.z > hi.z) continue;
      if (block.known(l)) fn(k, block.voxel(l));
    }
  };
  // Small boxes probe their blocks; large ones scan the map's blocks.
  const double box_blocks = double(bhi.x - blo.x + 1) * double(bhi.y - blo.y + 1) * double(bhi.z - blo.z + 1);
  if (box_blocks <= static_cast<double>(map.blocks().block_count())) {
    for (std::int32_t z = blo.z; z <= bhi.z; ++z)
      for (std::int32_t y = blo.y; y <= bhi.y; ++y)
        for (std::int32_t x = blo.x; x <= bhi.x; ++x) {
          const BlockKey bk{x, y, z};
          if (const auto* block = map.blocks().find(bk)) visit_block(bk, *block);
        }
  } else {
    for (const BlockKey& bk : map.blocks().sorted_block_keys()) {
      if (bk.x < blo.x || bk.y < blo.y || bk.z < blo.z || bk.x > bhi.x || bk.y > bhi.y || bk.z > bhi.z) continue;
      visit_block(bk, *map.blocks().find(bk));
    }
  }
}
}  // namespace

void for_each_voxel_in_box(const MetricMap& map, const Bounds& box, VoxelState state,
                           const std::function<void(const VoxelKey&)>& fn) {
  if (state == VoxelState::Unknown) return;
  for_each_known_in_box(map, box, [&](const VoxelKey& k, const SemanticVoxel& v) {
    if (map.occupancy().state(v.log_odds) == state) fn(k);
  });
}

std::vector<VoxelKey> frontier_voxels(const MetricMap& map, const Bounds& box) {
  std::vector<VoxelKey> out;
  MetricMap::Blocks::ConstAccessor access(map.blocks());
  for_each_known_in_box(map, box, [&](const VoxelKey& k, const SemanticVoxel& v) {
    if (map.occupancy().state(v.log_odds) != VoxelState::Free) return;
    static constexpr int kOffsets[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const auto& d : kOffsets) {
      const VoxelKey n{k.x + d[0], k.y + d[1], k.z + d[2]};
      const SemanticBlock* b = access.block(n);
      if (!b || !b->known(local_index(n))) {
        out.push_back(k);
        return;
      }
    }
  });
  return out;
}

}  // namespace sarmap::metric
