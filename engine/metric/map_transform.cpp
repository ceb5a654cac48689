#include "engine/metric/map_transform.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <tuple>

namespace sarmap::metric {
namespace {

// The moved map's blocks that may hold a voxel of `block`: those the
// transformed corners of the block's box span.
void add_covered_blocks(const BlockKey& block, double resolution, const Pose& transform,
                        std::set<std::tuple<int, int, int>>& out) {
  const double edge = kBlockEdge * resolution;
  const Eigen::Vector3d origin(block.x * edge, block.y * edge, block.z * edge);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d p =
        transform * (origin + edge * Eigen::Vector3d(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1));
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  if (!within_map_limits(lo.x(), lo.y(), lo.z()) || !within_map_limits(hi.x(), hi.y(), hi.z())) {
    lo = lo.cwiseMax(-kMaxCoordinate), hi = hi.cwiseMin(kMaxCoordinate);
    if ((lo.array() > hi.array()).any()) return;
  }
  const double inv = 1.0 / resolution;
  const BlockKey first = block_of(key_of(lo.x(), lo.y(), lo.z(), inv));
  const BlockKey last = block_of(key_of(hi.x(), hi.y(), hi.z(), inv));
  for (int z = first.z; z <= last.z; ++z) {
    for (int y = first.y; y <= last.y; ++y) {
      for (int x = first.x; x <= last.x; ++x) out.emplace(z, y, x);
    }
  }
}

}  // namespace

MetricMap transformed_map(const MetricMap& map, const Pose& transform) {
  MetricMap moved(map.settings());
  const double resolution = map.resolution(), inv = map.inv_resolution();
  std::set<std::tuple<int, int, int>> targets;  // (z, y, x): the files' block order
  for (const BlockKey& key : map.blocks().sorted_block_keys()) add_covered_blocks(key, resolution, transform, targets);
  const Pose back = transform.inverse();
  MetricMap::Blocks::ConstAccessor source(map.blocks());
  // Where a moved voxel looks in the source map: its centre, and eight
  // points a quarter voxel from it towards its corners, which land in the
  // source voxels it overlaps most. All nine fall in one source voxel when
  // the transform maps the grid onto itself.
  const double q = resolution / 4;
  std::array<Eigen::Vector3d, 9> offsets;
  offsets[0] = Eigen::Vector3d::Zero();
  for (int c = 0; c < 8; ++c) offsets[c + 1] = Eigen::Vector3d(c & 1 ? q : -q, c & 2 ? q : -q, c & 4 ? q : -q);
  for (const auto& [z, y, x] : targets) {
    const BlockKey block{x, y, z};
    DenseVoxels voxels{};
    bool any = false;
    for (int l = 0; l < kBlockVoxels; ++l) {
      const Eigen::Vector3d centre = moved.center_of(voxel_of(block, l));
      if (!within_map_limits(centre.x(), centre.y(), centre.z())) continue;
      // The most occupied source voxel it overlaps: resampling never opens a
      // gap in a wall one voxel thick (it may thicken it by one).
      std::optional<SemanticVoxel> best;
      for (const Eigen::Vector3d& offset : offsets) {
        const Eigen::Vector3d from = back * (centre + offset);
        if (!within_map_limits(from.x(), from.y(), from.z())) continue;
        const std::optional<SemanticVoxel> v = source.find(key_of(from.x(), from.y(), from.z(), inv));
        if (v && v->known() && (!best || v->log_odds > best->log_odds)) best = v;
      }
      if (!best) continue;
      voxels[l] = *best;
      any = true;
    }
    if (any) moved.blocks().assign(block, voxels);
  }
  return moved;
}

}  // namespace sarmap::metric
