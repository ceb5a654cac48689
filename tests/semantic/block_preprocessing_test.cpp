// Tests the DGCNN block preprocessing: partition membership and dropped-point
// counts on a hand-built cloud, sampling counts and determinism, and features
// against the Python definition (fixture from dgcnn_reference.py features).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/npy.hpp"
#include "engine/semantic/dgcnn/block_features.hpp"
#include "engine/semantic/dgcnn/block_partition.hpp"
#include "engine/semantic/dgcnn/block_sampling.hpp"

namespace sarmap {
namespace {

void add_points(PointBuffer& cloud, float x, float y, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) cloud.push_back(x + 0.001f * static_cast<float>(i % 50), y, 0.0f);
}

TEST(BlockPartition, MembershipAndDroppedCount) {
  PointBuffer cloud;
  add_points(cloud, 0.2f, 0.2f, 600);  // block (0, 0): kept
  add_points(cloud, 1.3f, 0.4f, 100);  // block (1, 0): dropped, fewer than 500
  add_points(cloud, 0.5f, 2.5f, 500);  // block (0, 2): exactly min_points, kept
  BlockPartitionSettings settings;
  settings.min_points = 500;
  const BlockPartition part = partition_blocks(cloud, settings);
  ASSERT_EQ(part.blocks.size(), 2u);
  EXPECT_EQ(part.blocks[0].points.size(), 600u);
  EXPECT_DOUBLE_EQ(part.blocks[0].origin_x, 0.0);
  EXPECT_DOUBLE_EQ(part.blocks[0].origin_y, 0.0);
  EXPECT_EQ(part.blocks[1].points.size(), 500u);
  EXPECT_DOUBLE_EQ(part.blocks[1].origin_y, 2.0);
  EXPECT_EQ(part.blocks[1].points.front(), 700u);
  EXPECT_EQ(part.dropped_points, 100u);
  EXPECT_EQ(part.covered[650], 0);
  EXPECT_EQ(part.covered[0], 1);
}

TEST(BlockPartition, OverlappingStrideCountsEachPointInEveryCoveringBlock) {
  PointBuffer cloud;
  cloud.push_back(0.1f, 0.1f, 0.0f);   // only block (0,0)
  cloud.push_back(0.75f, 0.1f, 0.0f);  // blocks x 0 and 1 (origins 0, 0.5)
  cloud.push_back(0.75f, 0.75f, 0.0f); // four blocks
  BlockPartitionSettings settings;
  settings.stride = 0.5;
  settings.min_points = 1;
  const BlockPartition part = partition_blocks(cloud, settings);
  std::size_t memberships = 0;
  for (const Block& b : part.blocks) {
    memberships += b.points.size();
    for (std::uint32_t p : b.points) {
      EXPECT_GE(cloud.x()[p], b.origin_x);
      EXPECT_LT(cloud.x()[p], b.origin_x + 1.0);
      EXPECT_GE(cloud.y()[p], b.origin_y);
      EXPECT_LT(cloud.y()[p], b.origin_y + 1.0);
    }
  }
  EXPECT_EQ(memberships, 1u + 2u + 4u);
  EXPECT_EQ(part.dropped_points, 0u);
}

TEST(BlockPartition, RejectsBadSettings) {
  PointBuffer cloud;
  cloud.push_back(0.0f, 0.0f, 0.0f);
  BlockPartitionSettings settings;
  settings.stride = 2.0;
  EXPECT_THROW(partition_blocks(cloud, settings), Error);
  settings.stride = 0.0;
  settings.block_size = 0.0;
  EXPECT_THROW(partition_blocks(cloud, settings), Error);
  settings.block_size = 1.0;
  cloud.push_back(1e30f, 0.0f, 0.0f);  // absurd span: refused, not an integer overflow
  EXPECT_THROW(partition_blocks(cloud, settings), Error);
}

// A tiny stride puts every point in (block / stride)^2 blocks: 1e-6 m had
// taken over 4 GB. The bound: 16 x 16 blocks per point, refused past it.
TEST(BlockPartition, StrideBelowASixteenthOfTheBlockIsRefused) {
  PointBuffer cloud;
  cloud.push_back(0.1f, 0.1f, 0.0f);
  BlockPartitionSettings settings;
  settings.min_points = 1;
  settings.stride = 1.0 / kMaxBlockOverlap;
  EXPECT_NO_THROW(partition_blocks(cloud, settings));
  settings.stride = 1e-6;
  try {
    partition_blocks(cloud, settings);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("over 256 blocks"), std::string::npos) << e.what();
  }
}

TEST(BlockSampling, MoreThanTargetIsDistinctAndDeterministic) {
  const auto a = sample_block(10000, 4096, 42, 3);
  ASSERT_EQ(a.size(), 4096u);
  EXPECT_EQ(std::set<std::uint32_t>(a.begin(), a.end()).size(), 4096u);
  EXPECT_TRUE(std::all_of(a.begin(), a.end(), [](std::uint32_t v) { return v < 10000; }));
  EXPECT_EQ(a, sample_block(10000, 4096, 42, 3));
  EXPECT_NE(a, sample_block(10000, 4096, 42, 4));
  EXPECT_NE(a, sample_block(10000, 4096, 43, 3));
}

TEST(BlockSampling, FewerThanTargetKeepsEveryPointAndRepeats) {
  const auto a = sample_block(700, 4096, 1, 0);
  ASSERT_EQ(a.size(), 4096u);
  std::vector<int> seen(700, 0);
  for (std::uint32_t v : a) {
    ASSERT_LT(v, 700u);
    ++seen[v];
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c >= 1; }));
  EXPECT_EQ(a, sample_block(700, 4096, 1, 0));
  EXPECT_THROW(sample_block(0, 4096, 1, 0), Error);
}

TEST(BlockFeatures, MatchPythonReference) {
  const NpyArray pts = read_npy_f32(SARMAP_TEST_DATA_DIR "/dgcnn/features_points.npy");
  ASSERT_EQ(pts.shape.size(), 2u);
  ASSERT_EQ(pts.shape[1], 6u);
  const std::size_t m = pts.shape[0];
  PointBuffer cloud;
  cloud.enable_colors();
  std::vector<std::uint32_t> idx;
  for (std::size_t i = 0; i < m; ++i) {
    const float* r = pts.values.data() + i * 6;
    cloud.push_back(r[0], r[1], r[2]);
    cloud.red()[i] = static_cast<std::uint8_t>(r[3]);
    cloud.green()[i] = static_cast<std::uint8_t>(r[4]);
    cloud.blue()[i] = static_cast<std::uint8_t>(r[5]);
    idx.push_back(static_cast<std::uint32_t>(i));
  }
  BlockFrame frame;
  frame.origin_x = 2.0;  // FEATURE_ORIGIN in dgcnn_reference.py
  frame.origin_y = -3.0;
  for (const bool rgb : {false, true}) {
    const NpyArray expected =
        read_npy_f32(std::string(SARMAP_TEST_DATA_DIR) + (rgb ? "/dgcnn/features_c9.npy" : "/dgcnn/features_c6.npy"));
    const std::vector<float> got = block_features(cloud, idx, frame, rgb);
    ASSERT_EQ(got.size(), expected.values.size());
    for (std::size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i], expected.values[i]) << "value " << i << " rgb " << rgb;
  }
}

}  // namespace
}  // namespace sarmap
