// Map bounds: which blocks the radius and the block budget drop (exact, on
// blocks placed by hand), and that equal distances are broken the same way
// whatever the hash order. (The Mapper's use of them: tests/pipeline/mapper_test.cpp.)
#include "engine/metric/map_bounds.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

#include "engine/core/error.hpp"

namespace sarmap::metric {
namespace {

// Blocks of 0.4 m at 0.05 m voxels; block (i, 0, 0) has its centre at x = 0.4 i + 0.2.
MetricMap map_with_blocks(const std::vector<BlockKey>& keys) {
  MetricMap map(settings_at_resolution(0.05));
  for (const BlockKey& k : keys) map.blocks().set_voxel(voxel_of(k, 0), {100, {}});
  return map;
}

std::vector<BlockKey> kept(const MetricMap& map) {
  std::vector<BlockKey> keys = map.blocks().sorted_block_keys();
  std::sort(keys.begin(), keys.end(), [](const BlockKey& a, const BlockKey& b) {
    return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
  });
  return keys;
}

TEST(MapBounds, RadiusDropsExactlyTheBlocksWhoseCentreIsBeyondIt) {
  MetricMap map = map_with_blocks({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {-3, 0, 0}, {0, 5, 0}});
  // Centres at x = 0.2, 0.6, 1.0, 1.4, -1.0 and (0.2, 2.2); radius 1.0 from the origin.
  EXPECT_EQ(drop_blocks_beyond(map, Eigen::Vector3d::Zero(), 1.05), 2u);
  EXPECT_EQ(kept(map), (std::vector<BlockKey>{{-3, 0, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}}));
  EXPECT_EQ(drop_blocks_beyond(map, Eigen::Vector3d::Zero(), 1.05), 0u);
}

TEST(MapBounds, BudgetDropsTheFarthestFirstAndBreaksTiesByKey) {
  // Centres at x = 0.2, 1.0, -1.0, -0.2, 1.8: (2,0,0) and (-3,0,0) are
  // equally far from the origin.
  MetricMap map = map_with_blocks({{0, 0, 0}, {2, 0, 0}, {-3, 0, 0}, {-1, 0, 0}, {4, 0, 0}});
  const Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  EXPECT_EQ(drop_farthest_blocks(map, centre, 5), 0u);
  EXPECT_EQ(drop_farthest_blocks(map, centre, 3), 2u);
  // 1.8 goes, then of the tie at 1.0 the larger key in (z, y, x) order: (2,0,0).
  EXPECT_EQ(kept(map), (std::vector<BlockKey>{{-3, 0, 0}, {-1, 0, 0}, {0, 0, 0}}));
  EXPECT_EQ(drop_farthest_blocks(map, centre, 0), 3u);
  EXPECT_TRUE(map.blocks().empty());
}

TEST(MapBounds, DroppedSpaceIsUnknownAgain) {
  MetricMap map = map_with_blocks({{10, 0, 0}});
  const VoxelKey corner{80, 0, 0};
  EXPECT_NE(map.state(corner), VoxelState::Unknown);
  MapBounds bounds;
  bounds.keep_radius = 2.0;
  EXPECT_EQ(apply_bounds(map, Eigen::Vector3d::Zero(), bounds), 1u);
  EXPECT_EQ(map.state(corner), VoxelState::Unknown);
}

TEST(MapBounds, RejectsABadRadius) {
  for (double radius : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    MapBounds bounds;
    bounds.keep_radius = radius;
    EXPECT_THROW(validate(bounds), Error);
  }
}

}  // namespace
}  // namespace sarmap::metric
