// FlatKeyIndex against a plain std::unordered_map on random insert, find and
// erase streams, and on runs of keys that share one home slot and wrap
// around the table's end (where an erase's backward shift can go wrong).
#include "engine/core/flat_key_index.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <unordered_map>
#include <vector>

namespace sarmap {
namespace {

// Every key the reference holds is found at its index, keys() lists them
// by index, and the indices are 0..n-1.
void expect_same(const FlatKeyIndex& index,
                 const std::unordered_map<std::uint64_t, std::uint32_t>& reference) {
  ASSERT_EQ(index.size(), reference.size());
  ASSERT_EQ(index.keys().size(), reference.size());
  for (const auto& [key, i] : reference) {
    ASSERT_EQ(index.find(key), i) << key;
    ASSERT_LT(i, reference.size());
    ASSERT_EQ(index.keys()[i], key);
  }
}

// What an erase does to the reference: the last index's key takes the freed index.
void erase_in_reference(std::unordered_map<std::uint64_t, std::uint32_t>& reference, std::uint64_t key) {
  const std::uint32_t freed = reference.at(key);
  const auto last = static_cast<std::uint32_t>(reference.size() - 1);
  reference.erase(key);
  for (auto& [k, i] : reference) {
    if (i == last) i = freed;
  }
}

TEST(FlatKeyIndex, MatchesAHashMapOnRandomInsertsFindsAndErases) {
  std::mt19937_64 rng(7);
  for (const std::uint64_t key_range : {std::uint64_t{40}, std::uint64_t{5000}, std::uint64_t{1} << 62}) {
    FlatKeyIndex index(16);
    std::unordered_map<std::uint64_t, std::uint32_t> reference;
    std::uniform_int_distribution<std::uint64_t> keys(0, key_range - 1);
    for (int step = 0; step < 20000; ++step) {
      const std::uint64_t key = keys(rng);
      const int op = static_cast<int>(rng() % 10);
      if (op < 5) {  // insert (or find the index of a held key)
        const auto it = reference.find(key);
        const std::uint32_t expected =
            it != reference.end() ? it->second : static_cast<std::uint32_t>(reference.size());
        ASSERT_EQ(index.find_or_insert(key), expected);
        reference.emplace(key, expected);
      } else if (op < 8) {  // erase
        const bool held = reference.count(key) > 0;
        const std::uint32_t freed = held ? reference.at(key) : FlatKeyIndex::kAbsent;
        ASSERT_EQ(index.erase(key), freed);
        if (held) erase_in_reference(reference, key);
      } else {
        const auto it = reference.find(key);
        ASSERT_EQ(index.find(key), it == reference.end() ? FlatKeyIndex::kAbsent : it->second);
      }
      if (step % 97 == 0) expect_same(index, reference);
    }
    expect_same(index, reference);
    index.clear();
    EXPECT_EQ(index.size(), 0u);
    for (const auto& entry : reference) EXPECT_EQ(index.find(entry.first), FlatKeyIndex::kAbsent);
  }
}

TEST(FlatKeyIndex, ErasesFromRunsThatShareAHomeSlotAndWrapAround) {
  // A table of 16 slots holds 7 keys before it grows: five share a home
  // slot (the last one, so their run wraps to the table's start; the first;
  // one in the middle) and two more have the next slot as home, so runs
  // interleave; all are erased in random orders.
  for (const std::size_t home : {std::size_t{15}, std::size_t{0}, std::size_t{13}}) {
    std::vector<std::uint64_t> same_home;
    for (std::uint64_t k = 1; same_home.size() < 8; ++k) {
      if ((mix_key(k) & 15) == home) same_home.push_back(k);
    }
    std::mt19937_64 rng(home);
    for (int trial = 0; trial < 200; ++trial) {
      FlatKeyIndex index(8);  // 16 slots
      std::unordered_map<std::uint64_t, std::uint32_t> reference;
      std::vector<std::uint64_t> keys(same_home.begin(), same_home.begin() + 5);
      for (std::uint64_t k = 1000; keys.size() < 7; ++k) {
        if ((mix_key(k) & 15) == ((home + 1) & 15)) keys.push_back(k);
      }
      std::shuffle(keys.begin(), keys.end(), rng);
      for (const std::uint64_t k : keys) reference.emplace(k, index.find_or_insert(k));
      std::shuffle(keys.begin(), keys.end(), rng);
      for (const std::uint64_t k : keys) {
        ASSERT_NE(index.erase(k), FlatKeyIndex::kAbsent);
        erase_in_reference(reference, k);
        expect_same(index, reference);
        ASSERT_EQ(index.find(k), FlatKeyIndex::kAbsent);
      }
      EXPECT_EQ(index.size(), 0u);
    }
  }
}

}  // namespace
}  // namespace sarmap
