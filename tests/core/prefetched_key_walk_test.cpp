// walk_keys_prefetched against a plain loop over the same points: the same
// points visited in the same order with the same keys and repeat marks, on
// random ranges with runs of equal keys and unkeyed points, and every key's
// slot prefetched before the key is visited.
#include "engine/core/prefetched_key_walk.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <random>
#include <set>
#include <tuple>
#include <vector>

namespace sarmap {
namespace {

// Records the prefetched keys; stands for FlatKeyIndex.
struct RecordingTable {
  mutable std::set<std::uint64_t> prefetched;
  mutable std::size_t prefetches = 0;
  void prefetch(std::uint64_t key) const {
    prefetched.insert(key);
    ++prefetches;
  }
};

using Visit = std::tuple<std::size_t, std::uint64_t, bool>;

std::vector<Visit> plain_walk(const std::vector<std::optional<std::uint64_t>>& keys, std::size_t begin,
                              std::size_t end) {
  std::vector<Visit> visits;
  std::optional<std::uint64_t> previous;
  for (std::size_t i = begin; i < end; ++i) {
    if (!keys[i]) continue;
    visits.emplace_back(i, *keys[i], previous == keys[i]);
    previous = keys[i];
  }
  return visits;
}

TEST(PrefetchedKeyWalk, VisitsAsAPlainLoopOnRandomRangesWithRunsAndGaps) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    // Lengths around the batch size and far beyond it, some ranges empty.
    const std::size_t n = std::uniform_int_distribution<std::size_t>(0, 5 * kPrefetchBatch + 3)(rng);
    std::vector<std::optional<std::uint64_t>> keys(n);
    std::uint64_t key = rng();
    for (auto& k : keys) {
      const int what = std::uniform_int_distribution<int>(0, 9)(rng);
      if (what == 0) continue;  // no key: skipped
      if (what <= 3)
        key = rng() % 8;  // a few small keys, 0 among them
      else if (what == 4)
        key = rng();  // a new key anywhere
      k = key;        // otherwise the run goes on
    }
    const std::size_t begin = n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n)(rng);
    const std::size_t end = std::uniform_int_distribution<std::size_t>(begin, n)(rng);

    RecordingTable table;
    std::vector<Visit> visits;
    walk_keys_prefetched(
        table, begin, end,
        [&](std::size_t i, std::uint64_t& key) {
          if (keys[i]) key = *keys[i];
          return keys[i].has_value();
        },
        [&](std::size_t i, std::uint64_t k, bool repeat) {
          EXPECT_EQ(table.prefetched.count(k), 1u) << "key " << k << " visited before it was prefetched";
          visits.emplace_back(i, k, repeat);
        });
    EXPECT_EQ(visits, plain_walk(keys, begin, end))
        << "trial " << trial << ", range " << begin << ".." << end;
    EXPECT_EQ(table.prefetches, visits.size());
  }
}

TEST(PrefetchedKeyWalk, ARunAcrossABatchBoundaryStaysARepeatAndSkippedPointsDoNotBreakIt) {
  const std::size_t n = 2 * kPrefetchBatch + 5;
  std::vector<std::optional<std::uint64_t>> keys(n, std::uint64_t{42});
  keys[kPrefetchBatch - 1] = std::nullopt;  // a gap just before the boundary
  keys[kPrefetchBatch] = std::nullopt;
  RecordingTable table;
  std::size_t first_visits = 0, repeats = 0;
  walk_keys_prefetched(
      table, 0, n,
      [&](std::size_t i, std::uint64_t& key) {
        if (keys[i]) key = *keys[i];
        return keys[i].has_value();
      },
      [&](std::size_t, std::uint64_t, bool repeat) { repeat ? ++repeats : ++first_visits; });
  EXPECT_EQ(first_visits, 1u);
  EXPECT_EQ(repeats, n - 3);
  // Every keyed point's slot, repeats included.
  EXPECT_EQ(table.prefetches, n - 2);
}

}  // namespace
}  // namespace sarmap
