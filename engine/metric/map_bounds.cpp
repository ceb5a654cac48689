#include "engine/metric/map_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "engine/core/error.hpp"

namespace sarmap::metric {

namespace {

Eigen::Vector3d block_centre(const MetricMap& map, const BlockKey& b) {
  const double edge = map.resolution() * kBlockEdge;
  return {(b.x + 0.5) * edge, (b.y + 0.5) * edge, (b.z + 0.5) * edge};
}

struct BlockDistance {
  double squared;
  BlockKey key;
};

std::vector<BlockDistance> block_distances(const MetricMap& map, const Eigen::Vector3d& centre) {
  std::vector<BlockDistance> all;
  all.reserve(map.blocks().block_count());
  map.blocks().for_each_block([&](const BlockKey& key, const auto&) {
    all.push_back({(block_centre(map, key) - centre).squaredNorm(), key});
  });
  return all;
}

}  // namespace

void validate(const MapBounds& bounds) {
  if (!(bounds.keep_radius >= 0.0) || !std::isfinite(bounds.keep_radius)) {
    throw Error(ErrorCode::InvalidArgument,
                "map bounds: keep radius must be finite and >= 0 (0 = no limit), got " +
                    std::to_string(bounds.keep_radius));
  }
}

std::size_t drop_blocks_beyond(MetricMap& map, const Eigen::Vector3d& centre, double radius) {
  std::size_t dropped = 0;
  for (const BlockDistance& b : block_distances(map, centre)) {
    if (b.squared > radius * radius) dropped += map.blocks().erase(b.key) ? 1 : 0;
  }
  return dropped;
}

std::size_t drop_farthest_blocks(MetricMap& map, const Eigen::Vector3d& centre, std::size_t max_blocks) {
  if (map.blocks().block_count() <= max_blocks) return 0;
  std::vector<BlockDistance> all = block_distances(map, centre);
  const std::size_t drop = all.size() - max_blocks;
  // Only the farthest `drop` need ordering among themselves.
  const auto farther = [](const BlockDistance& a, const BlockDistance& b) {
    return std::tie(a.squared, a.key.z, a.key.y, a.key.x) > std::tie(b.squared, b.key.z, b.key.y, b.key.x);
  };
  std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(drop - 1), all.end(), farther);
  for (std::size_t i = 0; i < drop; ++i) map.blocks().erase(all[i].key);
  return drop;
}

std::size_t apply_bounds(MetricMap& map, const Eigen::Vector3d& centre, const MapBounds& bounds) {
  std::size_t dropped = 0;
  if (bounds.keep_radius > 0.0) dropped += drop_blocks_beyond(map, centre, bounds.keep_radius);
  if (bounds.max_blocks > 0) dropped += drop_farthest_blocks(map, centre, bounds.max_blocks);
  return dropped;
}

}  // namespace sarmap::metric
