// Point queries, ray casts to the first occupied voxel, box iteration,
// frontiers and coarse views, on small hand-built maps.
#include "engine/metric/map_queries.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "engine/core/error.hpp"
#include "engine/metric/coarse_view.hpp"
#include "engine/metric/ray_integrator.hpp"

namespace sarmap::metric {
namespace {

// A wall of wall-class points at x = 1.0..1.05 seen from the origin.
MetricMap wall_map() {
  MetricMap map(settings_at_resolution(0.05));
  RayIntegrator integrator;
  PointBuffer pts;
  pts.enable_labels();
  for (int y = -4; y <= 4; ++y)
    for (int z = -4; z <= 4; ++z) {
      pts.push_back(1.025f, 0.025f + 0.05f * y, 0.025f + 0.05f * z);
      pts.labels()[pts.size() - 1] = static_cast<std::uint8_t>(ClassId::Wall);
    }
  for (int i = 0; i < 3; ++i) integrator.integrate(map, pts, {0.025, 0.025, 0.025});
  return map;
}

TEST(MapQueries, StateProbabilityAndClassAtPoints) {
  const MetricMap map = wall_map();
  EXPECT_EQ(map.state_at({1.03, 0.03, 0.03}), VoxelState::Occupied);
  EXPECT_EQ(map.class_at({1.03, 0.03, 0.03}), ClassId::Wall);
  EXPECT_GT(map.probability_at({1.03, 0.03, 0.03}), 0.9);
  EXPECT_EQ(map.state_at({0.5, 0.03, 0.03}), VoxelState::Free);
  EXPECT_EQ(map.class_at({0.5, 0.03, 0.03}), ClassId::Unknown);
  EXPECT_LT(map.probability_at({0.5, 0.03, 0.03}), 0.3);
  EXPECT_EQ(map.state_at({1.5, 0.03, 0.03}), VoxelState::Unknown);
  EXPECT_DOUBLE_EQ(map.probability_at({1.5, 0.03, 0.03}), 0.5);
  EXPECT_EQ(map.state_at({20000, 0, 0}), VoxelState::Unknown);
  const MapCounts c = map.counts();
  EXPECT_EQ(c.occupied, 81u);
  EXPECT_EQ(c.known, c.free + c.occupied);
}

TEST(MapQueries, CastRayFindsTheFirstOccupiedVoxel) {
  const MetricMap map = wall_map();
  const auto hit = cast_ray(map, {0.03, 0.03, 0.03}, {1, 0, 0}, 5.0);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->voxel, (VoxelKey{20, 0, 0}));
  EXPECT_NEAR(hit->distance, 0.995, 1e-3);
  EXPECT_FALSE(cast_ray(map, {0.03, 0.03, 0.03}, {1, 0, 0}, 0.5));
  EXPECT_FALSE(cast_ray(map, {0.03, 0.03, 0.03}, {-1, 0, 0}, 5.0));
  EXPECT_THROW(cast_ray(map, {0, 0, 0}, {0, 0, 0}, 1.0), Error);
}

TEST(MapQueries, BoxIterationAndFrontiers) {
  const MetricMap map = wall_map();
  Bounds box;
  box.extend(Eigen::Vector3d(0.9, -0.05, -0.05));
  box.extend(Eigen::Vector3d(1.1, 0.05, 0.05));
  std::vector<VoxelKey> occupied;
  for_each_voxel_in_box(map, box, VoxelState::Occupied, [&](const VoxelKey& k) { occupied.push_back(k); });
  EXPECT_EQ(occupied.size(), 4u);  // x = 20, y and z in {-1, 0}
  for (const auto& k : occupied) EXPECT_EQ(k.x, 20);
  Bounds all;
  all.extend(Eigen::Vector3d(-2, -2, -2));
  all.extend(Eigen::Vector3d(2, 2, 2));
  const auto frontier = frontier_voxels(map, all);
  ASSERT_FALSE(frontier.empty());
  for (const auto& k : frontier) {
    EXPECT_EQ(map.state(k), VoxelState::Free);
    int unknown = 0;
    for (const VoxelKey& n : {VoxelKey{k.x + 1, k.y, k.z}, VoxelKey{k.x - 1, k.y, k.z}, VoxelKey{k.x, k.y + 1, k.z},
                              VoxelKey{k.x, k.y - 1, k.z}, VoxelKey{k.x, k.y, k.z + 1}, VoxelKey{k.x, k.y, k.z - 1}}) {
      unknown += map.state(n) == VoxelState::Unknown;
    }
    EXPECT_GT(unknown, 0);
  }
}

TEST(CoarseView, AnyOccupiedChildMakesTheParentOccupiedWithSummedClass) {
  MetricMap map(settings_at_resolution(0.05));
  auto& blocks = map.blocks();
  // Coarse (x2) voxel (0,0,0) covers voxels 0..1 on each axis.
  blocks.set_voxel({0, 0, 0}, {map.occupancy().min(), {}});
  blocks.set_voxel({1, 0, 0}, {map.occupancy().max(), {0, 0, 120, 0, 0, 0}});
  blocks.set_voxel({1, 1, 0}, {map.occupancy().max(), {0, 100, 0, 0, 0, 0}});
  blocks.set_voxel({0, 1, 1}, {map.occupancy().max(), {0, 100, 0, 0, 0, 0}});
  blocks.set_voxel({2, 0, 0}, {map.occupancy().min(), {}});
  const CoarseView view(map, 2);
  EXPECT_DOUBLE_EQ(view.resolution(), 0.1);
  const CoarseVoxel v = view.voxel({0, 0, 0});
  EXPECT_EQ(v.state, VoxelState::Occupied);
  EXPECT_EQ(v.class_id, ClassId::Terrain);  // 200 terrain against 120 wall
  EXPECT_EQ(v.evidence[1], 200);
  EXPECT_EQ(view.voxel({1, 0, 0}).state, VoxelState::Free);
  EXPECT_EQ(view.voxel({1, 1, 1}).state, VoxelState::Unknown);
  EXPECT_EQ(view.voxel({50, 0, 0}).state, VoxelState::Unknown);
  EXPECT_EQ(view.known_voxels().size(), 2u);
  const CoarseView eight(map, 8);
  EXPECT_EQ(eight.voxel_at({0.01, 0.01, 0.01}).state, VoxelState::Occupied);
  EXPECT_EQ(eight.known_voxels().size(), 1u);
  EXPECT_THROW(CoarseView(map, 3), Error);
}

}  // namespace
}  // namespace sarmap::metric
