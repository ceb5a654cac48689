// Block map and keys: packing at the limits, negative coordinates, the
// accessor's one-look-up-per-block caching.
#include "engine/metric/block_map.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace sarmap::metric
