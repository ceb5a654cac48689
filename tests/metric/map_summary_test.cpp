// summarize_map: the counts agree with MetricMap::counts(), occupied voxels
// are counted by their dominant class, the bounds are the voxels' faces, and
// uniform blocks and whole uniform 2 x 2 x 2 groups are counted as stored.
#include "engine/metric/map_summary.hpp"

#include <gtest/gtest.h>

#include "engine/metric/ray_integrator.hpp"
#include "tests/metric/hand_made_map.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap::metric {
namespace {

void expect_near(const Eigen::Vector3d& got, const Eigen::Vector3d& want) {
  EXPECT_NEAR((got - want).cwiseAbs().maxCoeff(), 0.0, 1e-9) << got.transpose() << " vs " << want.transpose();
}

TEST(MapSummary, CountsClassesAndBoundsOfAHandMadeMap) {
  const MetricMap map = testing::hand_made_map();
  const MapSummary s = summarize_map(map);
  EXPECT_EQ(s.counts.blocks, 2u);
  EXPECT_EQ(s.counts.occupied, 13u);
  EXPECT_EQ(s.counts.free, 6u);
  EXPECT_EQ(s.counts.known, 19u);
  EXPECT_EQ(s.occupied_by_class, testing::kHandMadeOccupiedByClass);
  expect_near(s.occupied_bounds.min, {-0.1, 0, 0});
  expect_near(s.occupied_bounds.max, {0.8, 2.4, 0.8});
  expect_near(s.known_bounds.min, {-0.8, 0, 0});
  expect_near(s.known_bounds.max, {0.8, 2.4, 0.8});
}

TEST(MapSummary, AgreesWithTheMapsOwnCountsAfterIntegration) {
  MetricMap map(settings_at_resolution(0.1));
  RayIntegrator integrator;
  testing::SyntheticRoom room;
  for (int f = 0; f < 3; ++f) {
    const auto scan = room.frame(f, 3, 40, 30);
    integrator.integrate(map, scan.points, scan.origin);
  }
  const MapSummary s = summarize_map(map);
  const MapCounts c = map.counts();
  EXPECT_EQ(s.counts.blocks, c.blocks);
  EXPECT_EQ(s.counts.known, c.known);
  EXPECT_EQ(s.counts.free, c.free);
  EXPECT_EQ(s.counts.occupied, c.occupied);
  std::size_t by_class = 0;
  for (const std::size_t n : s.occupied_by_class) by_class += n;
  EXPECT_EQ(by_class, c.occupied);
  EXPECT_GT(s.occupied_by_class[static_cast<std::size_t>(ClassId::Wall)], 0u);
  EXPECT_GT(s.occupied_by_class[static_cast<std::size_t>(ClassId::Terrain)], 0u);
  // The room is 6 x 4 x 2.5 m; what the camera saw lies within it, give or take a voxel.
  EXPECT_GE(s.occupied_bounds.min.minCoeff(), -0.2);
  EXPECT_LE(s.occupied_bounds.max.x(), 6.2);
  EXPECT_TRUE(s.known_bounds.contains(s.occupied_bounds.min));
  EXPECT_TRUE(s.known_bounds.contains(s.occupied_bounds.max));
}

// Every voxel of a block at one value.
DenseVoxels all_at(std::int16_t log_odds) {
  DenseVoxels voxels;
  for (SemanticVoxel& v : voxels) v = {log_odds, {}};
  return voxels;
}

TEST(MapSummary, CountsUniformBlocksAndWholeGroupsOfOneValue) {
  MetricMap map(settings_at_resolution(0.1));
  const std::int16_t free = map.occupancy().min();
  const auto group = [&](int x0, int y0, int z0, auto&& voxels_of) {
    for (int i = 0; i < 8; ++i) map.blocks().assign({x0 + (i & 1), y0 + ((i >> 1) & 1), z0 + (i >> 2)}, voxels_of(i));
  };
  // A whole group all free at one value, at negative keys (groups of -2..-1).
  group(-2, -2, -2, [&](int) { return all_at(free); });
  // A whole group of uniform blocks, one at another free value.
  group(2, 0, 0, [&](int i) { return all_at(i == 5 ? static_cast<std::int16_t>(free + 1) : free); });
  // A whole group whose one block holds class evidence in one voxel.
  group(0, 4, 0, [&](int i) {
    DenseVoxels v = all_at(free);
    if (i == 3) v[17].evidence[static_cast<std::size_t>(ClassId::Wall)] = 10;
    return v;
  });
  // Seven blocks of a group, and a block still all unknown.
  for (int i = 0; i < 7; ++i) map.blocks().assign({4 + (i & 1), (i >> 1) & 1, i >> 2}, all_at(free));
  map.blocks().find_or_create({10, 10, 10});
  // A block with two values is not uniform.
  DenseVoxels mixed = all_at(free);
  mixed[0].log_odds = map.occupancy().max();
  map.blocks().assign({12, 0, 0}, mixed);

  const MapSummary s = summarize_map(map);
  EXPECT_EQ(s.counts.blocks, 33u);
  EXPECT_EQ(s.uniform_blocks, 8u + 8u + 7u + 7u + 1u);
  EXPECT_EQ(s.blocks_in_uniform_groups, 8u);
}

TEST(MapSummary, AnEmptyMapHasEmptyBounds) {
  const MapSummary s = summarize_map(MetricMap(settings_at_resolution(0.05)));
  EXPECT_EQ(s.counts.known, 0u);
  EXPECT_TRUE(s.known_bounds.empty());
  EXPECT_TRUE(s.occupied_bounds.empty());
  EXPECT_EQ(s.uniform_blocks, 0u);
  EXPECT_EQ(s.blocks_in_uniform_groups, 0u);
}

}  // namespace
}  // namespace sarmap::metric
