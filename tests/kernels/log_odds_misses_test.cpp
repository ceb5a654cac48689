// The log-odds miss kernel at every instruction set against the reference,
// and the reference against OctoMap's rule (unknown counts as 0, a miss
// added and clamped, free below the threshold): random blocks holding every
// byte value (unknown among them) under random masks, the empty and the
// full mask, words with a single bit, and models at the byte's extremes,
// where a sum leaves the byte.
#include "kernels/log_odds_misses.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "tests/kernels/kernel_test_support.hpp"

namespace sarmap::kernels {
namespace {

using Block = std::array<std::int8_t, kLogOddsBlockVoxels>;
using Mask = std::array<std::uint64_t, kLogOddsBlockWords>;

void expect_levels_match_reference(const Block& block, const Mask& misses, const LogOddsMiss& update) {
  Block expected = block;
  Mask expected_free{};
  apply_log_odds_misses_reference(expected.data(), misses.data(), update, expected_free.data());
  for (SimdLevel level : test::supported_levels()) {
    Block got = block;
    Mask free{};
    free.fill(~std::uint64_t{0});  // every word is written, with or without misses
    apply_log_odds_misses(got.data(), misses.data(), update, free.data(), level);
    EXPECT_EQ(got, expected) << to_string(level);
    EXPECT_EQ(free, expected_free) << to_string(level);
  }
}

TEST(LogOddsMisses, ReferenceFollowsOctoMapsRule) {
  Block block{};
  for (int l = 0; l < kLogOddsBlockVoxels; ++l) block[l] = static_cast<std::int8_t>(l % 256 - 128);
  Mask misses{};
  for (int w = 0; w < kLogOddsBlockWords; ++w) misses[w] = w % 2 ? ~std::uint64_t{0} : 0x00ff00ff00ff00ffull;
  const LogOddsMiss update{-13, -64, 111, 0};
  Block after = block;
  Mask free{};
  apply_log_odds_misses_reference(after.data(), misses.data(), update, free.data());
  for (int l = 0; l < kLogOddsBlockVoxels; ++l) {
    const bool missed = (misses[l / 64] >> (l % 64)) & 1u;
    if (!missed) {
      EXPECT_EQ(after[l], block[l]);
      EXPECT_EQ((free[l / 64] >> (l % 64)) & 1u, 0u);
      continue;
    }
    const int base = block[l] == kUnknownLogOddsByte ? 0 : block[l];
    const int expected = std::clamp(base + update.miss, update.lowest, update.highest);
    EXPECT_EQ(after[l], expected) << l;
    EXPECT_EQ((free[l / 64] >> (l % 64)) & 1u, expected < update.threshold ? 1u : 0u) << l;
  }
}

TEST(LogOddsMisses, EveryLevelMatchesTheReferenceOnRandomBlocks) {
  std::mt19937_64 rng(20261205);
  std::uniform_int_distribution<int> byte(-128, 127);
  // OctoMap's defaults in 1/32 nat, then bounds and steps at the byte's extremes.
  const LogOddsMiss updates[] = {{-13, -64, 111, 0},     {-127, -127, 127, 0}, {-1, -127, 127, 127},
                                 {127, -127, 127, -127}, {-40, 5, 9, 7},       {-13, -64, 111, -64}};
  for (const LogOddsMiss& update : updates) {
    for (int round = 0; round < 50; ++round) {
      Block block;
      for (auto& v : block) v = static_cast<std::int8_t>(byte(rng));
      Mask misses;
      for (auto& word : misses) {
        // Dense, sparse, empty and full words.
        switch (rng() % 4) {
          case 0:
            word = rng();
            break;
          case 1:
            word = rng() & rng() & rng();
            break;
          case 2:
            word = 0;
            break;
          default:
            word = ~std::uint64_t{0};
        }
      }
      expect_levels_match_reference(block, misses, update);
    }
  }
}

TEST(LogOddsMisses, SingleBitsAndUnknownVoxels) {
  Block block;
  block.fill(kUnknownLogOddsByte);
  for (int l = 0; l < kLogOddsBlockVoxels; l += 37) {
    Mask misses{};
    misses[l / 64] = std::uint64_t{1} << (l % 64);
    expect_levels_match_reference(block, misses, {-13, -64, 111, 0});
  }
  expect_levels_match_reference(block, Mask{}, {-13, -64, 111, 0});
}

}  // namespace
}  // namespace sarmap::kernels
