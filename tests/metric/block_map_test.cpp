// Block keys (packing at the limits, negative coordinates) and the pooled
// block records against a plain std::map on random creates, writes and
// erases: slots reused, empty pages freed, addresses stable while it grows.
#include "engine/metric/block_map.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <tuple>
#include <vector>

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

// A record as the map sees one: any fixed-size value, empty when default-constructed.
struct TestRecord {
  std::array<std::int32_t, 5> values{};
  friend bool operator==(const TestRecord&, const TestRecord&) = default;
};
using TestMap = BlockMap<TestRecord>;

TEST(BlockMap, CreatesBlocksEmptyAndFindsThem) {
  TestMap map;
  EXPECT_EQ(map.find(BlockKey{0, 0, 0}), nullptr);
  auto& b = map.find_or_create(BlockKey{-2, 3, 4});
  EXPECT_EQ(b, TestRecord{});
  b.values[1] = 5;
  EXPECT_EQ(map.find(BlockKey{-2, 3, 4})->values[1], 5);
  EXPECT_EQ(map.block_count(), 1u);
  EXPECT_EQ(&map.find_or_create(BlockKey{-2, 3, 4}), &b);
  map.find_or_create(BlockKey{0, 0, -1});
  map.find_or_create(BlockKey{5, -5, -1});
  const auto keys = map.sorted_block_keys();
  ASSERT_EQ(keys.size(), 3u);
  EXPECT_EQ(keys[0], (BlockKey{5, -5, -1}));  // z, then y, then x
  EXPECT_EQ(keys[1], (BlockKey{0, 0, -1}));
  EXPECT_TRUE(map.erase(BlockKey{0, 0, -1}));
  EXPECT_FALSE(map.erase(BlockKey{0, 0, -1}));
  EXPECT_EQ(map.block_count(), 2u);
}

using ReferenceRecords = std::map<std::tuple<int, int, int>, TestRecord>;

void expect_same_records(const TestMap& map, const ReferenceRecords& reference) {
  ASSERT_EQ(map.block_count(), reference.size());
  std::size_t visited = 0;
  map.for_each_block([&](const BlockKey& key, const TestRecord& record) {
    ++visited;
    const auto it = reference.find({key.x, key.y, key.z});
    ASSERT_NE(it, reference.end()) << key.x << " " << key.y << " " << key.z;
    ASSERT_EQ(record, it->second);
    ASSERT_EQ(map.find(key), &record);
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

TEST(BlockMap, PooledRecordsMatchAPlainMapOnRandomCreatesWritesAndErases) {
  std::mt19937 rng(11);
  // Few distinct keys, so creates, erases and re-creates of one key mix;
  // negative and far keys included.
  std::uniform_int_distribution<int> coord(-6, 6);
  TestMap map;
  ReferenceRecords reference;
  for (int step = 0; step < 30000; ++step) {
    const int far = rng() % 8 == 0 ? 100000 : 0;
    const BlockKey key{coord(rng) + far, coord(rng), coord(rng) - far};
    const auto ref_key = std::make_tuple(key.x, key.y, key.z);
    const int op = static_cast<int>(rng() % 8);
    if (op < 4) {  // create (or find) and write
      auto& record = map.find_or_create(key);
      auto [it, created] = reference.try_emplace(ref_key);
      if (created) {
        ASSERT_EQ(record, TestRecord{}) << "a new block is empty, also in a reused slot";
      }
      record.values[static_cast<std::size_t>(step % 5)] = step;
      it->second = record;
    } else if (op < 7) {
      ASSERT_EQ(map.erase(key), reference.erase(ref_key) > 0);
      ASSERT_EQ(map.find(key), nullptr);
    } else {
      const auto it = reference.find(ref_key);
      const TestRecord* found = map.find(key);
      ASSERT_EQ(found == nullptr, it == reference.end());
      if (found) {
        ASSERT_EQ(*found, it->second);
      }
    }
    if (step % 251 == 0) expect_same_records(map, reference);
  }
  expect_same_records(map, reference);
  map.clear();
  EXPECT_TRUE(map.empty());
  EXPECT_EQ(map.memory_bytes(), TestMap().memory_bytes());
}

TEST(BlockMap, DroppedBlocksSlotsAreReusedAndEmptyPagesFreed) {
  constexpr int kPages = 6;
  const int blocks = static_cast<int>(kPages * TestMap::kPageBlocks);
  TestMap map;
  const auto key = [](int i) { return BlockKey{i % 40, i / 40, -3}; };
  for (int i = 0; i < blocks; ++i) map.find_or_create(key(i)).values[0] = 1;
  const std::size_t full = map.memory_bytes();
  EXPECT_GE(full, blocks * sizeof(TestRecord));
  // Drop every other block, then as many new ones: no more storage than before.
  for (int i = 0; i < blocks; i += 2) ASSERT_TRUE(map.erase(key(i)));
  for (int i = 0; i < blocks; i += 2) ASSERT_EQ(map.find_or_create(key(blocks + i)), TestRecord{});
  EXPECT_EQ(map.block_count(), static_cast<std::size_t>(blocks));
  EXPECT_EQ(map.memory_bytes(), full);
  // The kept blocks kept their records.
  for (int i = 1; i < blocks; i += 2) ASSERT_EQ(map.find(key(i))->values[0], 1) << i;
  // Dropping all but one page's worth frees the other pages (the key table keeps its size).
  for (int i = 1; i < blocks; i += 2) map.erase(key(i));
  for (int i = 0; i < blocks && map.block_count() > TestMap::kPageBlocks; i += 2) map.erase(key(blocks + i));
  EXPECT_EQ(map.memory_bytes(), full - (kPages - 1) * TestMap::kPageBlocks * sizeof(TestRecord));
}

TEST(BlockMap, RecordsKeepTheirAddressesWhileTheMapGrows) {
  TestMap map;
  auto* first = &map.find_or_create(BlockKey{1, 2, 3});
  first->values[3] = 42;
  for (int i = 0; i < 5000; ++i) map.find_or_create(BlockKey{i, -i, i % 7});  // pages and table grow
  EXPECT_EQ(map.find(BlockKey{1, 2, 3}), first);
  EXPECT_EQ(first->values[3], 42);
}

}  // namespace
}  // namespace sarmap::metric
