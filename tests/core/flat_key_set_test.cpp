// Tests of engine/core/flat_key_set.hpp against std::unordered_set: random
// keys across many growths, keys that share a home slot, the smallest and
// largest packed keys, and the bytes it counts.
#include "engine/core/flat_key_set.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <unordered_set>
#include <vector>

#include "engine/metric/voxel_key.hpp"

namespace sarmap {
namespace {

TEST(FlatKeySet, AgreesWithAStandardSetThroughGrowth) {
  std::mt19937_64 rng(3);
  FlatKeySet set(4);
  std::unordered_set<std::uint64_t> reference;
  for (int i = 0; i < 200000; ++i) {
    // Few distinct keys at first (many repeats), then mostly new ones.
    const std::uint64_t range = i < 50000 ? 5000 : (std::uint64_t{1} << 40);
    const std::uint64_t key = rng() % range;
    ASSERT_EQ(set.insert(key), reference.insert(key).second) << "insert " << i;
    ASSERT_EQ(set.size(), reference.size());
  }
  for (int i = 0; i < 100000; ++i) {
    const std::uint64_t key = i % 2 == 0 ? rng() % 5000 : rng() % (std::uint64_t{1} << 40);
    ASSERT_EQ(set.contains(key), reference.count(key) == 1) << "key " << key;
  }
  for (const std::uint64_t key : reference) ASSERT_TRUE(set.contains(key)) << "key " << key;
  // At most half full, in whole slots of 8 bytes.
  EXPECT_GE(set.memory_bytes(), 2 * set.size() * sizeof(std::uint64_t));
  EXPECT_EQ(set.memory_bytes() % sizeof(std::uint64_t), 0u);
}

TEST(FlatKeySet, KeysSharingAHomeSlotAndTheEndsOfThePackedRange) {
  FlatKeySet set(16);  // 32 slots
  // Keys whose home slot (mix_key & 31) is the same: probed past each other.
  std::vector<std::uint64_t> same_home;
  for (std::uint64_t k = 1; same_home.size() < 8; ++k) {
    if ((mix_key(k) & 31) == (mix_key(1) & 31)) same_home.push_back(k);
  }
  for (std::uint64_t k : same_home) EXPECT_TRUE(set.insert(k));
  for (std::uint64_t k : same_home) {
    EXPECT_TRUE(set.contains(k));
    EXPECT_FALSE(set.insert(k));
  }
  const auto low = static_cast<std::int32_t>(-metric::kPackOffset), high = static_cast<std::int32_t>(metric::kPackOffset - 1);
  const std::uint64_t lowest = metric::pack(low, low, low), highest = metric::pack(high, high, high);
  EXPECT_EQ(lowest, 0u);
  EXPECT_NE(highest, FlatKeySet::kEmpty);
  EXPECT_FALSE(set.contains(lowest));
  EXPECT_TRUE(set.insert(lowest));
  EXPECT_TRUE(set.insert(highest));
  EXPECT_TRUE(set.contains(lowest));
  EXPECT_TRUE(set.contains(highest));
  EXPECT_EQ(set.size(), same_home.size() + 2);
}

}  // namespace
}  // namespace sarmap
