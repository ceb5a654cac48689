// Tests score carry-back (engine/semantic/dgcnn/score_carry_back.hpp): the grid
// nearest-sample search against brute force (random, walls, tall blocks,
// ties), a hand-built block, and averaging over overlapping blocks.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/semantic/dgcnn/block_partition.hpp"
#include "engine/semantic/dgcnn/block_sampling.hpp"
#include "engine/semantic/dgcnn/score_carry_back.hpp"

namespace sarmap {
namespace {

TEST(ScoreCarryBack, HandBuiltBlock) {
  PointBuffer cloud;
  cloud.push_back(0.1f, 0.1f, 0.0f);  // sampled as sample 0
  cloud.push_back(0.9f, 0.9f, 0.0f);  // sampled as sample 1
  cloud.push_back(0.2f, 0.1f, 0.0f);  // nearest: point 0
  cloud.push_back(0.8f, 0.9f, 1.0f);  // xy near point 1, but z: distance 1.005 to 1 vs ~1.27 to 0 -> 1
  Block block;
  block.points = {0, 1, 2, 3};
  const std::vector<std::uint32_t> samples = {0, 1, 0};
  const auto near = nearest_sample(cloud, block, samples);
  EXPECT_EQ(near, (std::vector<std::uint32_t>{0, 1, 0, 1}));
  EXPECT_EQ(near, nearest_sample_reference(cloud, block, samples));

  ScoreAccumulator acc(4, 2);
  const std::vector<float> scores = {0.9f, 0.1f, 0.2f, 0.8f, 0.9f, 0.1f};
  acc.add_block(cloud, block, samples, scores);
  EXPECT_EQ(acc.mean(3), (std::vector<float>{0.2f, 0.8f}));
  EXPECT_EQ(acc.mean(2), (std::vector<float>{0.9f, 0.1f}));
  EXPECT_THROW(acc.add_block(cloud, block, samples, std::vector<float>(5)), Error);
}

TEST(ScoreCarryBack, GridMatchesBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 0.999f);
  PointBuffer cloud;
  for (int i = 0; i < 3000; ++i) cloud.push_back(3.0f + u(rng), -2.0f + u(rng), 2.0f * u(rng));
  // Clustered points too: a tight blob far from most samples.
  for (int i = 0; i < 300; ++i) cloud.push_back(3.05f + 0.01f * u(rng), -1.95f + 0.01f * u(rng), 0.0f);
  BlockPartitionSettings settings;
  settings.min_points = 1;
  const BlockPartition part = partition_blocks(cloud, settings);
  ASSERT_EQ(part.blocks.size(), 1u);
  for (std::size_t target : {50u, 700u}) {
    const auto samples = sample_block(part.blocks[0].points.size(), target, 9, target);
    EXPECT_EQ(nearest_sample(cloud, part.blocks[0], samples),
              nearest_sample_reference(cloud, part.blocks[0], samples));
  }
}

// The grid's edge cases: a wall (every sample of a column stacked in z), a
// block far taller than the grid's layers (clamped into its end layers),
// points above and below every sample, and samples at equal distances (the
// lowest sample index wins, as in the brute force).
TEST(ScoreCarryBack, GridMatchesBruteForceOnWallsTallBlocksAndTies) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> u(0.0f, 0.999f);
  PointBuffer cloud;
  for (int i = 0; i < 2000; ++i) cloud.push_back(u(rng), 0.5f + 0.002f * u(rng), 2.5f * u(rng));  // a wall
  for (int i = 0; i < 400; ++i) cloud.push_back(u(rng), u(rng), 0.0f);                             // its floor
  for (int i = 0; i < 50; ++i) cloud.push_back(u(rng), u(rng), 40.0f * u(rng));                    // a mast
  cloud.push_back(0.5f, 0.5f, -3.0f), cloud.push_back(0.5f, 0.5f, 60.0f);                          // beyond all
  for (int i = 0; i < 8; ++i) cloud.push_back(0.25f, 0.25f, 1.0f);  // one position, many copies
  for (const float dx : {-0.05f, 0.05f}) cloud.push_back(0.7f + dx, 0.8f, 1.0f);  // equidistant pair
  cloud.push_back(0.7f, 0.8f, 1.0f);
  BlockPartitionSettings settings;
  settings.min_points = 1;
  settings.block_size = 1.0;
  settings.stride = 1.0;
  const BlockPartition part = partition_blocks(cloud, settings);
  ASSERT_EQ(part.blocks.size(), 1u);
  const Block& block = part.blocks[0];
  for (std::size_t target : {30u, 400u, 2048u}) {
    const auto samples = sample_block(block.points.size(), target, 4, target);
    EXPECT_EQ(nearest_sample(cloud, block, samples), nearest_sample_reference(cloud, block, samples)) << target;
  }
  // Samples chosen by hand: the pair equidistant from the last point, the
  // copies at one position, and nothing sampled near the ends.
  const std::size_t n = block.points.size();
  std::vector<std::uint32_t> chosen;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t p = block.points[i];
    if (cloud.z()[p] == 1.0f || (i % 97 == 0 && cloud.z()[p] < 2.5f)) chosen.push_back(static_cast<std::uint32_t>(i));
  }
  ASSERT_GT(chosen.size(), 10u);
  EXPECT_EQ(nearest_sample(cloud, block, chosen), nearest_sample_reference(cloud, block, chosen));
  const std::vector<std::uint32_t> one{static_cast<std::uint32_t>(n - 1)};
  EXPECT_EQ(nearest_sample(cloud, block, one), std::vector<std::uint32_t>(n, 0));
}

TEST(ScoreCarryBack, OverlappingBlocksAverage) {
  PointBuffer cloud;
  cloud.push_back(0.5f, 0.5f, 0.0f);
  Block a, b;
  a.points = {0};
  b.points = {0};
  ScoreAccumulator acc(1, 2);
  const std::vector<std::uint32_t> samples = {0};
  acc.add_block(cloud, a, samples, std::vector<float>{1.0f, 0.0f});
  acc.add_block(cloud, b, samples, std::vector<float>{0.0f, 1.0f});
  EXPECT_EQ(acc.hits(0), 2u);
  EXPECT_EQ(acc.mean(0), (std::vector<float>{0.5f, 0.5f}));
}

}  // namespace
}  // namespace sarmap
