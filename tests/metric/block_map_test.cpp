// Block map and keys: packing at the limits, negative coordinates, the
// accessor's one-look-up-per-block caching, and the pooled blocks against a
// plain std::map of blocks on random creates, writes and erases.
#include "engine/metric/block_map.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "engine/metric/semantic_voxel.hpp"

namespace sarmap::metric {
namespace {

TEST(VoxelKey, FloorForNegativeCoordinatesLikeOctoMap) {
  const VoxelKey k = key_of(-0.01, 0.0, 0.049, 1.0 / 0.05);
  EXPECT_EQ(k, (VoxelKey{-1, 0, 0}));
  EXPECT_EQ(block_of(VoxelKey{-1, -8, -9}), (BlockKey{-1, -1, -2}));
  EXPECT_EQ(local_index(VoxelKey{-1, 0, 0}), 7);
  for (int l : {0, 7, 63, 64, 300, 511}) {
    const VoxelKey v = voxel_of(BlockKey{-3, 5, -1}, l);
    EXPECT_EQ(block_of(v), (BlockKey{-3, 5, -1}));
    EXPECT_EQ(local_index(v), l);
  }
}

TEST(VoxelKey, PackRoundTripsAtTheTenKilometreLimit) {
  const double inv = 1.0 / kMinResolution;
  const VoxelKey lo = key_of(-kMaxCoordinate, -kMaxCoordinate, -kMaxCoordinate, inv);
  const VoxelKey hi = key_of(kMaxCoordinate, kMaxCoordinate, kMaxCoordinate, inv);
  for (const VoxelKey& v : {lo, hi}) {
    const BlockKey b = block_of(v);
    EXPECT_EQ(unpack_block(pack(b)), b);
  }
  EXPECT_NE(pack(lo), pack(hi));
  EXPECT_FALSE(within_map_limits(10000.01, 0, 0));
  EXPECT_FALSE(within_map_limits(0, std::nan(""), 0));
  EXPECT_TRUE(within_map_limits(-10000.0, 10000.0, 0));
}

TEST(BlockMap, CreatesBlocksUnknownAndFindsThem) {
  BlockMap<SemanticVoxel> map;
  EXPECT_EQ(map.find(BlockKey{0, 0, 0}), nullptr);
  auto& b = map.find_or_create(BlockKey{-2, 3, 4});
  EXPECT_FALSE(b.voxels[17].known());
  b.voxels[17].log_odds = 5;
  EXPECT_EQ(map.voxel(voxel_of(BlockKey{-2, 3, 4}, 17))->log_odds, 5);
  EXPECT_EQ(map.block_count(), 1u);
  EXPECT_EQ(&map.find_or_create(BlockKey{-2, 3, 4}), &b);
  map.find_or_create(BlockKey{0, 0, -1});
  map.find_or_create(BlockKey{5, -5, -1});
  const auto keys = map.sorted_block_keys();
  ASSERT_EQ(keys.size(), 3u);
  EXPECT_EQ(keys[0], (BlockKey{5, -5, -1}));  // z, then y, then x
  EXPECT_EQ(keys[1], (BlockKey{0, 0, -1}));
  EXPECT_TRUE(map.erase(BlockKey{0, 0, -1}));
  EXPECT_EQ(map.block_count(), 2u);
}

TEST(BlockMap, AccessorLooksUpOncePerBlock) {
  BlockMap<SemanticVoxel> map;
  BlockMap<SemanticVoxel>::Accessor access(map);
  for (int x = 0; x < 24; ++x) access.get_or_create(VoxelKey{x, 1, 1}).log_odds = static_cast<std::int16_t>(x);
  EXPECT_EQ(access.lookups(), 3u);  // three blocks along x
  EXPECT_EQ(map.block_count(), 3u);
  BlockMap<SemanticVoxel>::ConstAccessor reader(map);
  for (int x = 0; x < 24; ++x) EXPECT_EQ(reader.find(VoxelKey{x, 1, 1})->log_odds, x);
  EXPECT_EQ(reader.find(VoxelKey{100, 1, 1}), nullptr);
  EXPECT_EQ(reader.lookups(), 4u);
  // A find() on a missing block does not create it, and a later create does.
  EXPECT_EQ(access.find(VoxelKey{-1, 0, 0}), nullptr);
  access.get_or_create(VoxelKey{-1, 0, 0});
  EXPECT_EQ(map.block_count(), 4u);
}

// The reference: every block's voxels by key, in a std::map.
using ReferenceBlocks = std::map<std::tuple<int, int, int>, std::array<SemanticVoxel, kBlockVoxels>>;

void expect_same_blocks(const BlockMap<SemanticVoxel>& map, const ReferenceBlocks& reference) {
  ASSERT_EQ(map.block_count(), reference.size());
  std::size_t visited = 0;
  map.for_each_block([&](const BlockKey& key, const BlockMap<SemanticVoxel>::Block& block) {
    ++visited;
    const auto it = reference.find({key.x, key.y, key.z});
    ASSERT_NE(it, reference.end()) << key.x << " " << key.y << " " << key.z;
    ASSERT_EQ(std::memcmp(block.voxels.data(), it->second.data(), sizeof(block.voxels)), 0);
    ASSERT_EQ(map.find(key), &block);
  });
  ASSERT_EQ(visited, reference.size());
  std::vector<BlockKey> sorted;
  for (const auto& entry : reference) {
    const auto& [x, y, z] = entry.first;
    sorted.push_back({x, y, z});
  }
  std::sort(sorted.begin(), sorted.end(), [](const BlockKey& a, const BlockKey& b) {
    return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x);
  });
  ASSERT_EQ(map.sorted_block_keys(), sorted);
}

TEST(BlockMap, PooledBlocksMatchAPlainMapOnRandomCreatesWritesAndErases) {
  std::mt19937 rng(11);
  // Few distinct keys, so creates, erases and re-creates of one key mix;
  // negative and far keys included.
  std::uniform_int_distribution<int> coord(-6, 6);
  std::uniform_int_distribution<int> voxel(0, kBlockVoxels - 1);
  BlockMap<SemanticVoxel> map;
  ReferenceBlocks reference;
  const auto random_key = [&] {
    const int far = rng() % 8 == 0 ? 100000 : 0;
    return BlockKey{coord(rng) + far, coord(rng), coord(rng) - far};
  };
  for (int step = 0; step < 30000; ++step) {
    const BlockKey key = random_key();
    const auto ref_key = std::make_tuple(key.x, key.y, key.z);
    const int op = static_cast<int>(rng() % 8);
    if (op < 4) {  // create (or find) and write a voxel
      auto& block = map.find_or_create(key);
      auto [it, created] = reference.try_emplace(ref_key);
      if (created) {
        for (const SemanticVoxel& v : block.voxels) ASSERT_FALSE(v.known()) << "a new block is all unknown";
      }
      const int l = voxel(rng);
      block.voxels[l].log_odds = static_cast<std::int16_t>(step % 3000);
      block.voxels[l].evidence[step % kClassCount] = static_cast<std::int16_t>(step);
      it->second[l] = block.voxels[l];
    } else if (op < 7) {
      ASSERT_EQ(map.erase(key), reference.erase(ref_key) > 0);
      ASSERT_EQ(map.find(key), nullptr);
    } else {
      const SemanticVoxel* v = map.voxel(voxel_of(key, 5));
      const auto it = reference.find(ref_key);
      ASSERT_EQ(v == nullptr, it == reference.end());
      if (v) {
        ASSERT_EQ(std::memcmp(v, &it->second[5], sizeof(SemanticVoxel)), 0);
      }
    }
    if (step % 251 == 0) expect_same_blocks(map, reference);
  }
  expect_same_blocks(map, reference);
  map.clear();
  EXPECT_TRUE(map.empty());
  EXPECT_EQ(map.memory_bytes(), BlockMap<SemanticVoxel>().memory_bytes());
}

TEST(BlockMap, DroppedBlocksSlotsAreReusedAndEmptyPagesFreed) {
  using Map = BlockMap<SemanticVoxel>;
  constexpr int kPages = 6;
  const int blocks = static_cast<int>(kPages * Map::kPageBlocks);
  Map map;
  const auto key = [](int i) { return BlockKey{i % 40, i / 40, -3}; };
  for (int i = 0; i < blocks; ++i) map.find_or_create(key(i)).voxels[i % kBlockVoxels].log_odds = 1;
  const std::size_t full = map.memory_bytes();
  // Drop every other block, then as many new ones: no more storage than before.
  for (int i = 0; i < blocks; i += 2) ASSERT_TRUE(map.erase(key(i)));
  for (int i = 0; i < blocks; i += 2) {
    const auto& block = map.find_or_create(key(blocks + i));
    for (const SemanticVoxel& v : block.voxels) ASSERT_FALSE(v.known()) << "a reused slot is all unknown";
  }
  EXPECT_EQ(map.block_count(), static_cast<std::size_t>(blocks));
  EXPECT_EQ(map.memory_bytes(), full);
  // The kept blocks kept their voxels.
  for (int i = 1; i < blocks; i += 2) ASSERT_EQ(map.find(key(i))->voxels[i % kBlockVoxels].log_odds, 1) << i;
  // Dropping all but one page's worth frees the other pages (the key table keeps its size).
  for (int i = 1; i < blocks; i += 2) map.erase(key(i));
  for (int i = 0; i < blocks; i += 2) {
    if (map.block_count() == Map::kPageBlocks) break;
    map.erase(key(blocks + i));
  }
  EXPECT_EQ(map.memory_bytes(), full - (kPages - 1) * Map::kPageBlocks * sizeof(Map::Block));
}

TEST(BlockMap, BlocksKeepTheirAddressesWhileTheMapGrows) {
  BlockMap<SemanticVoxel> map;
  auto* first = &map.find_or_create(BlockKey{1, 2, 3});
  first->voxels[9].log_odds = 42;
  for (int i = 0; i < 5000; ++i) map.find_or_create(BlockKey{i, -i, i % 7});  // pages and table grow
  EXPECT_EQ(map.find(BlockKey{1, 2, 3}), first);
  EXPECT_EQ(first->voxels[9].log_odds, 42);
}

}  // namespace
}  // namespace sarmap::metric
