// FlatKeyMap against a std::map on a random stream of inserts, updates
// through operator[] and finds: values stay with their keys, in insertion
// order, and a held key's value is never replaced by try_emplace.
#include "engine/core/flat_key_map.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <random>
#include <vector>

namespace sarmap {
namespace {

TEST(FlatKeyMap, MatchesAnOrderedMapOnRandomInsertsUpdatesAndFinds) {
  std::mt19937_64 rng(7);
  // Few distinct keys, so most operations meet a held key; small initial
  // capacity, so the index rehashes several times.
  std::uniform_int_distribution<std::uint64_t> key_of(0, 3000);
  std::uniform_int_distribution<int> op(0, 2);
  FlatKeyMap<std::int64_t> map(4);
  std::map<std::uint64_t, std::int64_t> reference;
  std::vector<std::uint64_t> order;  // keys in insertion order
  for (int step = 0; step < 20000; ++step) {
    const std::uint64_t key = key_of(rng) * 0x9e3779b97f4a7c15ull;  // spread over all 64 bits
    switch (op(rng)) {
      case 0: {
        const auto [index, inserted] = map.try_emplace(key, step);
        const bool is_new = reference.emplace(key, step).second;
        ASSERT_EQ(inserted, is_new);
        if (is_new) order.push_back(key);
        ASSERT_EQ(map.keys()[index], key);
        ASSERT_EQ(map.values()[index], reference.at(key));
        break;
      }
      case 1: {
        if (!reference.contains(key)) order.push_back(key);
        map[key] += step;
        reference[key] += step;
        break;
      }
      default: {
        const std::int64_t* found = map.find(key);
        const auto it = reference.find(key);
        ASSERT_EQ(found != nullptr, it != reference.end());
        ASSERT_EQ(map.index_of(key) != FlatKeyMap<std::int64_t>::kAbsent, it != reference.end());
        if (found) {
          ASSERT_EQ(*found, it->second);
        }
      }
    }
  }
  ASSERT_EQ(map.size(), reference.size());
  ASSERT_EQ(map.keys(), order);
  for (std::size_t i = 0; i < order.size(); ++i) ASSERT_EQ(map.values()[i], reference.at(order[i]));
}

TEST(FlatKeyMap, NewKeysAreValueInitialisedAndClearEmptiesIt) {
  struct Sums {
    int points;
    double height;
  };
  FlatKeyMap<Sums> map;
  EXPECT_TRUE(map.empty());
  map[42].points += 2;
  EXPECT_EQ(map[42].points, 2);
  EXPECT_EQ(map[42].height, 0.0);
  EXPECT_EQ(map[7].points, 0);
  EXPECT_EQ(map.size(), 2u);
  EXPECT_GT(map.memory_bytes(), 2 * sizeof(Sums));
  map.clear();
  EXPECT_TRUE(map.empty());
  EXPECT_EQ(map.find(42), nullptr);
  EXPECT_EQ(map.index_of(7), FlatKeyMap<Sums>::kAbsent);
  EXPECT_EQ(map.try_emplace(7, Sums{5, 1.0}).index, 0u);  // indices start again at 0
  EXPECT_EQ(map.find(7)->points, 5);
}

}  // namespace
}  // namespace sarmap
