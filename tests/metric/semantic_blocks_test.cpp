// The metric map's compact blocks against the dense representation they
// replaced (512 SemanticVoxel per block, in a std::map): random writes of
// voxels, evidence and whole blocks, and drops, read back voxel for voxel;
// uniform blocks without a slab, rows only for voxels with evidence, and the
// integrator's prepare / write / settle steps.
#include "engine/metric/semantic_blocks.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <random>
#include <tuple>

namespace sarmap::metric {
namespace {

using DenseMap = std::map<std::tuple<int, int, int>, DenseVoxels>;

bool same_voxel(const SemanticVoxel& a, const SemanticVoxel& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every block and voxel of the compact map equals the dense one's, and each
// block holds a row exactly for its voxels with evidence.
void expect_same(const SemanticBlocks& blocks, const DenseMap& dense) {
  ASSERT_EQ(blocks.block_count(), dense.size());
  std::size_t slabs = 0;
  for (const auto& [key, voxels] : dense) {
    const auto& [x, y, z] = key;
    const SemanticBlock* block = blocks.find(BlockKey{x, y, z});
    ASSERT_NE(block, nullptr);
    const DenseVoxels ours = block->dense();
    std::size_t with_evidence = 0;
    for (int l = 0; l < kBlockVoxels; ++l) {
      ASSERT_TRUE(same_voxel(ours[l], voxels[l])) << "block " << x << " " << y << " " << z << " voxel " << l;
      ASSERT_TRUE(same_voxel(block->voxel(l), voxels[l])) << l;
      ASSERT_EQ(block->holds_evidence(l), !no_evidence(voxels[l].evidence)) << l;
      with_evidence += no_evidence(voxels[l].evidence) ? 0 : 1;
    }
    ASSERT_EQ(block->row_count(), with_evidence);
    ASSERT_LE(block->row_count(), block->row_capacity());
    slabs += block->uniform_occupancy() ? 0 : 1;
  }
  ASSERT_EQ(blocks.slabs_in_use(), slabs);
}

SemanticVoxel random_voxel(std::mt19937& rng) {
  static constexpr std::int16_t kLogOdds[] = {kUnknownLogOdds, -64, -13, 0, 27, 111};
  SemanticVoxel v;
  v.log_odds = kLogOdds[rng() % 6];
  if (rng() % 3 == 0) {
    for (auto& e : v.evidence) e = static_cast<std::int16_t>(static_cast<int>(rng() % 255) - 127);
  } else if (rng() % 4 == 0) {
    v.evidence[rng() % kClassCount] = static_cast<std::int16_t>(1 + rng() % 127);
  }
  return v;
}

TEST(SemanticBlocks, MatchDenseBlocksOnRandomWritesAndDrops) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> coord(-12, 11);  // three blocks per axis
  SemanticBlocks blocks;
  DenseMap dense;
  for (int step = 0; step < 40000; ++step) {
    const VoxelKey key{coord(rng), coord(rng), coord(rng)};
    const BlockKey bk = block_of(key);
    const auto ref_key = std::make_tuple(bk.x, bk.y, bk.z);
    const int op = static_cast<int>(rng() % 100);
    if (op < 70) {
      const SemanticVoxel v = random_voxel(rng);
      blocks.set_voxel(key, v);
      dense[ref_key][static_cast<std::size_t>(local_index(key))] = v;
    } else if (op < 85) {
      SemanticBlock* block = blocks.find(bk);
      if (block == nullptr) continue;
      const ClassEvidence e = random_voxel(rng).evidence;
      blocks.set_evidence(*block, local_index(key), e);
      dense[ref_key][static_cast<std::size_t>(local_index(key))].evidence = e;
    } else if (op < 93) {
      // A whole block: uniform, uniform but for one voxel, or random.
      DenseVoxels voxels;
      const SemanticVoxel base = random_voxel(rng);
      const int kind = static_cast<int>(rng() % 3);
      for (int l = 0; l < kBlockVoxels; ++l) {
        voxels[l] = kind == 2 ? random_voxel(rng) : SemanticVoxel{base.log_odds, {}};
      }
      if (kind == 1) voxels[rng() % kBlockVoxels] = random_voxel(rng);
      blocks.assign(bk, voxels);
      dense[ref_key] = voxels;
    } else {
      ASSERT_EQ(blocks.erase(bk), dense.erase(ref_key) > 0);
    }
    if (step % 500 == 0) expect_same(blocks, dense);
  }
  expect_same(blocks, dense);
  for (const auto& [key, voxels] : dense) {
    const auto& [x, y, z] = key;
    for (int l = 0; l < kBlockVoxels; l += 37) {
      ASSERT_TRUE(same_voxel(*blocks.voxel(voxel_of(BlockKey{x, y, z}, l)), voxels[l]));
    }
  }
  EXPECT_FALSE(blocks.voxel(VoxelKey{1000, 0, 0}).has_value());
}

TEST(SemanticBlocks, UniformBlocksHoldNoSlabUntilAVoxelDiffers) {
  SemanticBlocks blocks;
  const std::size_t empty = blocks.memory_bytes();
  DenseVoxels free_space;
  free_space.fill(SemanticVoxel{-64, {}});
  for (int i = 0; i < 50; ++i) blocks.assign(BlockKey{i, 0, 0}, free_space);
  EXPECT_EQ(blocks.slabs_in_use(), 0u);
  const std::size_t uniform = blocks.memory_bytes();
  // A slab per block would be 50 KiB more: the records alone are far less.
  EXPECT_LT(uniform - empty, 50u * kBlockVoxels * sizeof(std::int8_t));
  // Writing the same value keeps the block uniform; another value expands it.
  blocks.set_voxel(voxel_of(BlockKey{3, 0, 0}, 7), {-64, {}});
  EXPECT_EQ(blocks.slabs_in_use(), 0u);
  blocks.set_voxel(voxel_of(BlockKey{3, 0, 0}, 7), {-13, {}});
  EXPECT_EQ(blocks.slabs_in_use(), 1u);
  EXPECT_EQ(blocks.voxel(voxel_of(BlockKey{3, 0, 0}, 7))->log_odds, -13);
  EXPECT_EQ(blocks.voxel(voxel_of(BlockKey{3, 0, 0}, 8))->log_odds, -64);
  // Evidence alone does not expand a block.
  blocks.set_voxel(voxel_of(BlockKey{4, 0, 0}, 9), {-64, {0, 5, 0, 0, 0, 0}});
  EXPECT_EQ(blocks.slabs_in_use(), 1u);
  EXPECT_EQ(blocks.find(BlockKey{4, 0, 0})->row_count(), 1u);
}

TEST(SemanticBlocks, PrepareWriteSettleCollapsesAndGivesStorageBack) {
  SemanticBlocks blocks;
  SemanticBlock& block = blocks.find_or_create(BlockKey{0, 0, 0});
  EXPECT_TRUE(block.uniform_occupancy());
  EXPECT_FALSE(block.known(0));
  // As the integrator's update: expand, room for 3 rows, write, settle.
  blocks.prepare(block, true, 3);
  ASSERT_FALSE(block.uniform_occupancy());
  EXPECT_GE(block.row_capacity(), 3u);
  const std::size_t expanded = blocks.memory_bytes();
  std::int8_t* slab = block.log_odds_slab();
  for (int l = 0; l < kBlockVoxels; ++l) slab[l] = stored_log_odds(-13);
  block.put_evidence(5, {0, 0, 40, 0, 0, 0});
  EXPECT_TRUE(SemanticBlocks::uniform_slab(block));
  blocks.settle(block, true);
  EXPECT_TRUE(block.uniform_occupancy());
  EXPECT_EQ(block.uniform_log_odds(), -13);
  EXPECT_EQ(block.evidence(5)[2], 40);
  EXPECT_EQ(blocks.slabs_in_use(), 0u);
  // The slab went back to the pool: the next expansion takes it, no new page.
  blocks.prepare(block, true, 0);
  EXPECT_EQ(block.log_odds_slab(), slab);
  EXPECT_EQ(block.log_odds(100), -13);
  slab[100] = 0;
  EXPECT_FALSE(SemanticBlocks::uniform_slab(block));
  blocks.settle(block, false);
  EXPECT_FALSE(block.uniform_occupancy());
  EXPECT_LT(blocks.memory_bytes(), expanded + 1024);  // no new page: a free list's bytes at most
  // The last row removed: the rows chunk goes back too.
  block.put_evidence(5, {});
  blocks.settle(block, false);
  EXPECT_EQ(block.row_capacity(), 0u);
  EXPECT_EQ(block.row_count(), 0u);
}

TEST(SemanticBlocks, EvidenceRowsGrowAndShrinkThroughTheirClasses) {
  SemanticBlocks blocks;
  DenseVoxels want;
  const BlockKey bk{-1, -1, -1};
  // Every voxel gains evidence, in a scattered order, then loses it again.
  std::vector<int> order(kBlockVoxels);
  for (int l = 0; l < kBlockVoxels; ++l) order[static_cast<std::size_t>(l)] = (l * 197) % kBlockVoxels;
  for (const int l : order) {
    const ClassEvidence e{0, static_cast<std::int16_t>(l % 127 + 1), 0, 0, 0, static_cast<std::int16_t>(-(l / 5))};
    blocks.set_voxel(voxel_of(bk, l), {100, e});
    want[static_cast<std::size_t>(l)] = {100, e};
  }
  const SemanticBlock& block = *blocks.find(bk);
  EXPECT_EQ(block.row_count(), 512u);
  EXPECT_EQ(block.row_capacity(), 512u);
  EXPECT_TRUE(std::memcmp(block.dense().data(), want.data(), sizeof want) == 0);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const int l = order[order.size() - 1 - i];
    blocks.set_voxel(voxel_of(bk, l), {100, {}});
    want[static_cast<std::size_t>(l)].evidence = {};
    if (i % 64 == 0) {
      ASSERT_TRUE(std::memcmp(block.dense().data(), want.data(), sizeof want) == 0) << i;
    }
    // Storage follows the rows down: never more than four times what they need.
    ASSERT_LT(block.row_capacity(), 4 * std::max<std::size_t>(4, 2 * block.row_count()) + 1);
  }
  EXPECT_EQ(block.row_count(), 0u);
  EXPECT_EQ(block.row_capacity(), 0u);
}

TEST(SemanticBlocks, ConstAccessorLooksUpOncePerBlock) {
  SemanticBlocks blocks;
  for (int x = 0; x < 24; ++x) blocks.set_voxel(VoxelKey{x, 1, 1}, {static_cast<std::int16_t>(x), {}});
  EXPECT_EQ(blocks.block_count(), 3u);
  SemanticBlocks::ConstAccessor reader(blocks);
  for (int x = 0; x < 24; ++x) EXPECT_EQ(reader.find(VoxelKey{x, 1, 1})->log_odds, x);
  EXPECT_FALSE(reader.find(VoxelKey{100, 1, 1}).has_value());
  EXPECT_EQ(reader.block(VoxelKey{100, 1, 2}), nullptr);  // the same block: no look-up
  EXPECT_EQ(reader.lookups(), 4u);
}

}  // namespace
}  // namespace sarmap::metric
