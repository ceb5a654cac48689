// ClassDelays against a plain reference: a list of (point, added at,
// classified at) kept by hand, through settles, renumbering, merging and a
// saved state, and the points still waiting by the scan that added them.
#include "engine/semantic/map/class_delays.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "engine/core/error.hpp"

namespace sarmap {
namespace {

constexpr std::uint32_t kGone = 0xffffffffu;

TEST(ClassDelays, RecordsEachPointsWaitOnceAndKeepsTheRestWaiting) {
  ClassDelays delays;
  delays.added(std::vector<std::uint32_t>{0, 1, 2}, 1);
  delays.settle(1, [](std::uint32_t p) { return p == 1; });  // classified in the scan that added it
  delays.added(std::vector<std::uint32_t>{3, 4}, 2);
  delays.settle(4, [](std::uint32_t p) { return p == 0 || p == 3; });
  EXPECT_EQ(delays.histogram(), (std::vector<std::uint64_t>{1, 0, 1, 1}));  // 1: 0 scans; 3: 2; 0: 3
  EXPECT_EQ(delays.recorded(), 3u);
  EXPECT_EQ(delays.waiting(), 2u);  // 2 and 4
  EXPECT_EQ(delays.quantile(0.5), 2u);
  EXPECT_EQ(delays.quantile(1.0), 3u);
  EXPECT_EQ(delays.quantile(0.0), 0u);
  // A settle from an index looks only at the points added since.
  delays.added(std::vector<std::uint32_t>{5}, 5);
  delays.settle(5, [](std::uint32_t) { return true; }, 2);
  EXPECT_EQ(delays.waiting(), 2u);
  EXPECT_EQ(delays.histogram()[0], 2u);
  // Renumbered after a forget: 2 forgotten, 4 becomes 1.
  std::vector<std::uint32_t> renumbered = {kGone, kGone, kGone, kGone, 1, kGone};
  delays.renumber(renumbered);
  EXPECT_EQ(delays.waiting(), 1u);
  EXPECT_TRUE(delays.consistent_with(2, 5));
  EXPECT_FALSE(delays.consistent_with(1, 5));
  EXPECT_FALSE(delays.consistent_with(2, 1));  // added at scan 2, after "scan 1"
  delays.settle(9, [](std::uint32_t p) { return p == 1; });
  EXPECT_EQ(delays.histogram()[7], 1u);  // added at 2, classified at 9
  EXPECT_EQ(delays.waiting(), 0u);
}

TEST(ClassDelays, MatchesAHandKeptListOnRandomSequences) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    ClassDelays delays;
    std::map<std::uint32_t, std::uint32_t> added_at;  // waiting points, the reference
    std::vector<std::uint64_t> reference(ClassDelays::kMaxDelay + 1, 0);
    std::uint32_t next = 0;
    for (std::uint32_t scan = 1; scan <= 60; ++scan) {
      std::vector<std::uint32_t> added;
      for (std::uint32_t n = rng() % 20; n > 0; --n) added.push_back(next++);
      delays.added(added, scan);
      for (std::uint32_t p : added) added_at[p] = scan;
      // A point gets its class with probability 1/8 per scan, by a hash of (point, scan).
      const auto has_class = [scan](std::uint32_t p) { return ((p * 2654435761u) ^ (scan * 40503u)) % 8 == 0; };
      delays.settle(scan, has_class);
      for (auto it = added_at.begin(); it != added_at.end();) {
        if (has_class(it->first)) {
          ++reference[scan - it->second];
          it = added_at.erase(it);
        } else {
          ++it;
        }
      }
    }
    std::vector<std::uint64_t> got = delays.histogram();
    got.resize(reference.size(), 0);
    ASSERT_EQ(got, reference) << "trial " << trial;
    ASSERT_EQ(delays.waiting(), added_at.size());
    // The waiting points by the scan that added them (points were numbered in order).
    for (std::uint32_t scan = 0; scan <= 61; ++scan) {
      std::vector<std::uint32_t> expected;
      for (const auto& [p, at] : added_at) {
        if (at == scan) expected.push_back(p);
      }
      ASSERT_EQ(delays.waiting_added_by(scan), expected) << "trial " << trial << ", scan " << scan;
    }
    // The saved state continues identically; merging adds the histograms.
    StateWriter out;
    delays.save_state(out);
    ClassDelays loaded;
    StateReader in(out.bytes(), "state");
    loaded.load_state(in);
    in.expect_end();
    EXPECT_EQ(loaded.histogram(), delays.histogram());
    EXPECT_EQ(loaded.waiting(), delays.waiting());
    loaded.merge(delays);
    EXPECT_EQ(loaded.recorded(), 2 * delays.recorded());
  }
}

TEST(ClassDelays, LongWaitsShareTheLastBinAndABadStateIsRefused) {
  ClassDelays delays;
  delays.added(std::vector<std::uint32_t>{0}, 1);
  delays.settle(5000, [](std::uint32_t) { return true; });
  EXPECT_EQ(delays.histogram().size(), ClassDelays::kMaxDelay + 1);
  EXPECT_EQ(delays.quantile(0.5), ClassDelays::kMaxDelay);
  StateWriter out;
  out.tag("CDLY");
  out.put_vector(std::vector<std::uint32_t>{1, 2, 3});  // three (point, scan) pairs declared, one and a half held
  out.put_vector(std::vector<std::uint64_t>{});
  StateReader in(out.bytes(), "state");
  EXPECT_THROW(delays.load_state(in), Error);
  // Waiting points are kept in the order of the scans that added them.
  StateWriter unordered;
  unordered.tag("CDLY");
  unordered.put_vector(std::vector<std::uint32_t>{0, 5, 1, 3});  // point 0 of scan 5, then point 1 of scan 3
  unordered.put_vector(std::vector<std::uint64_t>{});
  StateReader in2(unordered.bytes(), "state");
  EXPECT_THROW(delays.load_state(in2), Error);
}

}  // namespace
}  // namespace sarmap
