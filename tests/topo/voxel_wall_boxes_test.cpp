// Wall boxes from voxel columns: merging runs keeps exactly the runs' voxels
// (random columns, negative indices, gaps and other classes inside columns),
// a straight wall becomes one box, and the grown box's extent in metres.
#include "engine/topo/voxel_wall_boxes.hpp"

#include <gtest/gtest.h>

#include <random>

#include "tests/topo/columns_of_labels.hpp"

namespace sarmap::topo {
namespace {

using testing::columns_of;

TEST(VoxelWallBoxes, MergedBoxesHoldExactlyTheObstacleVoxels) {
  constexpr int kWidth = 14, kHeight = 11, kDepth = 9;
  const std::int32_t x0 = -5, y0 = -3, z0 = -2;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    // Walls of one height along rows and columns, so that merging has work, then random voxels over them.
    std::vector<ClassId> labels(static_cast<std::size_t>(kWidth) * kHeight * kDepth, ClassId::Unknown);
    auto at = [&](int x, int y, int z) -> ClassId& { return labels[x + kWidth * (y + kHeight * z)]; };
    const int wall_y = static_cast<int>(rng() % kHeight), wall_x = static_cast<int>(rng() % kWidth);
    for (int z = 1; z < 6; ++z) {
      for (int x = 0; x < kWidth; ++x) at(x, wall_y, z) = ClassId::Wall;
      for (int y = 0; y < kHeight; ++y) at(wall_x, y, z) = ClassId::Other;
    }
    const ClassId choices[] = {ClassId::Unknown, ClassId::Unknown, ClassId::Terrain, ClassId::Wall, ClassId::Other,
                               ClassId::InclinedRamp};
    for (int k = 0; k < 150; ++k) {
      at(static_cast<int>(rng() % kWidth), static_cast<int>(rng() % kHeight), static_cast<int>(rng() % kDepth)) =
          choices[rng() % 6];
    }
    const VoxelColumns columns = columns_of(labels, kWidth, kHeight, kDepth, x0, y0, z0);
    const std::vector<VoxelBox> runs = obstacle_runs(columns);
    const std::vector<VoxelBox> boxes = merge_runs(runs);
    EXPECT_LT(boxes.size(), runs.size()) << "seed " << seed;
    std::size_t volume = 0;
    for (const VoxelBox& b : boxes) {
      ASSERT_LE(b.x0, b.x1);
      ASSERT_LE(b.y0, b.y1);
      ASSERT_LE(b.z0, b.z1);
      volume += static_cast<std::size_t>(b.x1 - b.x0 + 1) * (b.y1 - b.y0 + 1) * (b.z1 - b.z0 + 1);
    }
    std::size_t obstacles = 0;
    for (int z = 0; z < kDepth; ++z) {
      for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
          const ClassId label = at(x, y, z);
          const bool obstacle = label == ClassId::Wall || label == ClassId::Other;
          obstacles += obstacle;
          bool in_box = false;
          for (const VoxelBox& b : boxes) in_box = in_box || b.contains(x0 + x, y0 + y, z0 + z);
          EXPECT_EQ(in_box, obstacle) << "seed " << seed << " voxel " << x0 + x << " " << y0 + y << " " << z0 + z;
        }
      }
    }
    // Every obstacle voxel in a box and volumes adding up to their count: no voxel in two boxes.
    EXPECT_EQ(volume, obstacles) << "seed " << seed;
  }
}

TEST(VoxelWallBoxes, AStraightWallIsOneBoxAndAGapSplitsIt) {
  constexpr int kWidth = 10, kHeight = 2, kDepth = 6;
  std::vector<ClassId> labels(static_cast<std::size_t>(kWidth) * kHeight * kDepth, ClassId::Unknown);
  for (int z = 1; z < 5; ++z) {
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) labels[x + kWidth * (y + kHeight * z)] = ClassId::Wall;
    }
  }
  const VoxelColumns wall = columns_of(labels, kWidth, kHeight, kDepth, 100, -7, 0);
  ASSERT_EQ(obstacle_runs(wall).size(), 20u);
  const std::vector<VoxelBox> one = merge_runs(obstacle_runs(wall));
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0], (VoxelBox{100, 109, -7, -6, 1, 4}));

  const geometry::OrientedBox grown = grown_box(one[0], 0.05, 0.2);
  EXPECT_NEAR(grown.center.x(), 105 * 0.05, 1e-12);
  EXPECT_NEAR(grown.center.y(), -6 * 0.05, 1e-12);
  EXPECT_NEAR(grown.center.z(), 3 * 0.05, 1e-12);
  EXPECT_NEAR(grown.half_extents.x(), 5 * 0.05 + 0.2, 1e-12);
  EXPECT_NEAR(grown.half_extents.y(), 0.05 + 0.2, 1e-12);
  EXPECT_NEAR(grown.half_extents.z(), 2 * 0.05 + 0.2, 1e-12);
  EXPECT_TRUE(grown.axes.isIdentity());

  // A terrain voxel inside one column splits its run; a missing column splits the wall.
  labels[3 + kWidth * (0 + kHeight * 2)] = ClassId::Terrain;
  for (int z = 1; z < 5; ++z) labels[6 + kWidth * (1 + kHeight * z)] = ClassId::Unknown;
  const std::vector<VoxelBox> split = merge_runs(obstacle_runs(columns_of(labels, kWidth, kHeight, kDepth, 100, -7, 0)));
  EXPECT_GT(split.size(), 1u);

  EXPECT_TRUE(obstacle_runs(VoxelColumns{}).empty());
  EXPECT_TRUE(merge_runs({}).empty());
}

}  // namespace
}  // namespace sarmap::topo
