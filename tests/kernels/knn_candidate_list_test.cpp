// Tests kernels/knn_candidate_list.hpp: a candidate's 64-bit key must order
// exactly like its (rank, index) pair, decode back to the rank, and the
// vector insertion must keep the list a reference sorted insertion would
// (checked here at the SSE4.2 baseline; the kNN tests run the wider
// instruction sets' insertions through whole lists).
#include "kernels/knn_candidate_list.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace sarmap::kernels {
namespace {

std::vector<float> awkward_ranks() {
  const float inf = std::numeric_limits<float>::infinity();
  return {-inf, -3.0e38f, -2.0f, -1.0f, -1e-30f, -1e-45f, -0.0f, 0.0f, 1e-45f, 1e-38f, 1e-30f,
          0.5f, 1.0f, 1.0000001f, 2.0f, 3.0e38f};
}

TEST(KnnCandidateList, KeysOrderLikeRankThenIndex) {
  std::vector<std::pair<float, std::uint32_t>> pairs;
  for (float rank : awkward_ranks()) {
    for (std::uint32_t id : {0u, 1u, 7u, 4095u, (1u << 24) - 1, 0xffffffffu}) pairs.emplace_back(rank, id);
  }
  for (const auto& a : pairs) {
    for (const auto& b : pairs) {
      const bool pair_less = a.first < b.first || (a.first == b.first && a.second < b.second);
      EXPECT_EQ(candidate_key(a.first, a.second) < candidate_key(b.first, b.second), pair_less)
          << a.first << "/" << a.second << " vs " << b.first << "/" << b.second;
    }
  }
}

TEST(KnnCandidateList, KeysDecodeToTheirRankAndIndex) {
  for (float rank : awkward_ranks()) {
    const std::int64_t key = candidate_key(rank, 12345u);
    EXPECT_EQ(rank_of_key(key), rank);
    EXPECT_FALSE(std::signbit(rank_of_key(key)) && rank == 0.0f) << "-0 is stored as +0";
    EXPECT_EQ(index_of_key(key), 12345u);
  }
}

TEST(KnnCandidateList, InsertionKeepsTheSmallestKeysInOrder) {
  using Arch = xsimd::sse4_2;
  constexpr std::size_t KL = keys_per_vector<Arch>();
  std::mt19937 rng(5);
  for (std::size_t slots : {1u, 2u, 3u, 20u, 28u, 72u}) {
    const std::size_t chunks = (slots + KL - 1) / KL;
    alignas(64) std::int64_t list[KL + 80];
    std::fill_n(list, KL, std::numeric_limits<std::int64_t>::min());
    std::fill_n(list + KL, chunks * KL, std::numeric_limits<std::int64_t>::max());
    std::vector<std::int64_t> inserted;
    // Few distinct ranks, so that many keys tie on the rank and order by index.
    std::uniform_int_distribution<int> rank(-4, 4);
    std::uniform_int_distribution<std::uint32_t> id(0, 50);
    for (int i = 0; i < 400; ++i) {
      const std::int64_t key = candidate_key(0.25f * static_cast<float>(rank(rng)), id(rng));
      if (key >= list[KL + slots - 1]) continue;  // as the kernel does: only what beats the last entry
      insert_candidate<Arch>(list + KL, chunks, key);
      inserted.push_back(key);
      std::sort(inserted.begin(), inserted.end());
      if (inserted.size() > slots) inserted.resize(slots);
      ASSERT_TRUE(std::equal(inserted.begin(), inserted.end(), list + KL)) << "slots " << slots << ", step " << i;
    }
  }
}

}  // namespace
}  // namespace sarmap::kernels
