// Map bounds: which blocks the radius and the block budget drop (exact, on
// blocks placed by hand), that equal distances are broken the same way
// whatever the hash order, and that the Mapper keeps a bounded map while
// still mapping what is near the sensor.
#include "engine/metric/map_bounds.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/pipeline/mapper.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap::metric {
namespace {

// Blocks of 0.4 m at 0.05 m voxels; block (i, 0, 0) has its centre at x = 0.4 i + 0.2.
MetricMap map_with_blocks(const std::vector<BlockKey>& keys) {
  MetricMap map(settings_at_resolution(0.05));
  for (const BlockKey& k : keys) map.blocks().find_or_create(k).voxels[0].log_odds = 100;
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
    pipeline::MapperConfig config;
    config.classifier.kind = "labels";
    config.bounds = bounds;
    EXPECT_THROW(pipeline::Mapper mapper(config), Error);
  }
}

TEST(MapBounds, MapperKeepsTheMapWithinItsBudgetAndRadius) {
  testing::SyntheticRoom room;
  pipeline::MapperConfig unbounded;
  unbounded.classifier.kind = "labels";
  pipeline::MapperConfig bounded = unbounded;
  bounded.bounds.keep_radius = 1.5;
  bounded.bounds.max_blocks = 60;
  pipeline::Mapper full(unbounded), small(bounded);
  Eigen::Vector3d last_origin;
  for (int f = 0; f < 4; ++f) {
    auto r = room.frame(f, 4, 128, 96);
    Scan a, b;
    a.points = r.points;
    b.points = r.points;
    a.origin = b.origin = last_origin = r.origin;
    full.integrate(a);
    small.integrate(b);
    EXPECT_LE(small.metric_map().blocks().block_count(), 60u);
  }
  ASSERT_GT(full.metric_map().blocks().block_count(), 60u);
  EXPECT_GT(small.blocks_dropped(), 0u);
  EXPECT_GT(small.profile().counter("metric", "blocks_dropped"), 0.0);
  const double edge = 0.05 * kBlockEdge;
  small.metric_map().blocks().for_each_block([&](const BlockKey& k, const auto&) {
    const Eigen::Vector3d c((k.x + 0.5) * edge, (k.y + 0.5) * edge, (k.z + 0.5) * edge);
    EXPECT_LE((c - last_origin).norm(), 1.5 + 1e-9);
  });
  // What is kept near the sensor is mapped as without bounds: the voxels of
  // the block holding the sensor agree.
  const VoxelKey here = *full.metric_map().key_at(last_origin);
  const BlockKey home = block_of(here);
  for (int local = 0; local < kBlockVoxels; ++local) {
    const VoxelKey v = voxel_of(home, local);
    EXPECT_EQ(small.metric_map().state(v), full.metric_map().state(v));
  }
}

}  // namespace
}  // namespace sarmap::metric
