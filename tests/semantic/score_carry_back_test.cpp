// Tests score carry-back (engine/semantic/dgcnn/score_carry_back.hpp): the grid
// nearest-sample search against brute force, a hand-built block, and averaging
// over overlapping blocks.
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
