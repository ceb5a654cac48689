// Tests kernels/knn.hpp against its scalar reference at every instruction set:
// the lists must be exactly the reference's on random 3-D to 70-D points,
// exact duplicates and copies, ties the float ranking cannot resolve, fewer
// points than k, all-equal points, and with 1 vs 2 threads.
#include "kernels/knn.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "tests/kernels/kernel_test_support.hpp"

namespace sarmap::kernels {
namespace {

// knn() at every instruction set gives exactly knn_reference()'s lists.
void expect_reference_lists(const std::vector<float>& p, std::size_t dim, std::size_t k) {
  const std::size_t n = p.size() / dim;
  std::vector<std::uint32_t> ref(n * k);
  knn_reference(p.data(), dim, n, dim, k, ref.data());
  for (SimdLevel level : test::supported_levels()) {
    KnnWorkspace ws;
    std::vector<std::uint32_t> got(n * k);
    knn(p.data(), dim, n, dim, k, level, ws, got.data());
    EXPECT_EQ(got, ref) << to_string(level);
  }
}

TEST(Knn, RandomPointsMatchReference) {
  // 13 and 70: the re-ranking's wide exact distance has a scalar tail past whole vectors.
  for (std::size_t dim : {3u, 64u, 5u, 13u, 70u}) {
    const std::size_t n = dim >= 64 ? 700 : 1100;
    expect_reference_lists(test::random_floats(n * dim, static_cast<unsigned>(dim)), dim, 20);
  }
}

// The candidate list spans several vectors (k 64 keeps 72) or a single slot.
TEST(Knn, SmallestAndLargestKMatchReference) {
  const auto p = test::random_floats(400 * 3, 21);
  for (std::size_t k : {std::size_t{1}, std::size_t{7}, kKnnMaxK}) {
    SCOPED_TRACE("k " + std::to_string(k));
    expect_reference_lists(p, 3, k);
  }
}

TEST(Knn, StridedInputUsesOnlyTheGivenChannels) {
  // 6 channels per point, kNN over the last three (as DGCNN's first layer).
  const std::size_t n = 300, k = 16;
  auto p = test::random_floats(n * 6, 11);
  std::vector<float> last3(n * 3);
  for (std::size_t i = 0; i < n; ++i) std::copy_n(&p[i * 6 + 3], 3, &last3[i * 3]);
  std::vector<std::uint32_t> ref(n * k);
  knn_reference(last3.data(), 3, n, 3, k, ref.data());
  for (SimdLevel level : test::supported_levels()) {
    KnnWorkspace ws;
    std::vector<std::uint32_t> got(n * k);
    knn(p.data() + 3, 6, n, 3, k, level, ws, got.data());
    EXPECT_EQ(got, ref) << to_string(level);
  }
}

TEST(Knn, DuplicatePointsBreakTiesByIndexExactly) {
  // Integer grid points, each present three times: every distance is an exact
  // small integer, so ties are exact and must be broken by index.
  std::vector<float> p;
  for (int copy = 0; copy < 3; ++copy) {
    for (int x = 0; x < 6; ++x) {
      for (int y = 0; y < 5; ++y) {
        for (int z = 0; z < 4; ++z) p.insert(p.end(), {float(x), float(y), float(z)});
      }
    }
  }
  expect_reference_lists(p, 3, 20);
}

TEST(Knn, NeighboursFarFromTheCentreAreExactWhereFloatRankingCannotTell) {
  // Two small clusters 2 km apart: centred on their common mean, every
  // coordinate is about 1000, so the float ranking |b|^2 - 2a.b rounds by
  // about 1 while neighbours within a cluster differ by 1e-4. The fast
  // candidates cannot be trusted here; the kernel must notice and still give
  // the reference's exact lists.
  std::vector<float> p;
  for (float centre : {1000.0f, -1000.0f}) {
    for (int x = 0; x < 7; ++x) {
      for (int y = 0; y < 6; ++y) {
        for (int z = 0; z < 5; ++z) p.insert(p.end(), {centre + 0.01f * x, 0.013f * y, 0.017f * z});
      }
    }
  }
  expect_reference_lists(p, 3, 20);
}

TEST(Knn, ManyCopiesOfFewPointsMatchReference) {
  // A sparse block padded by repetition: 30 points, 40 copies each, so every
  // row's k-th neighbour ties exactly with copies beyond its candidate list.
  const auto distinct = test::random_floats(30 * 3, 31);
  std::vector<float> p;
  for (int copy = 0; copy < 40; ++copy) p.insert(p.end(), distinct.begin(), distinct.end());
  expect_reference_lists(p, 3, 20);
}

TEST(Knn, FewerPointsThanKListsAllThenRepeatsTheNearest) {
  const std::size_t n = 7, k = 20;
  const auto p = test::random_floats(n * 3, 12);
  std::vector<std::uint32_t> ref(n * k);
  knn_reference(p.data(), 3, n, 3, k, ref.data());
  for (SimdLevel level : test::supported_levels()) {
    KnnWorkspace ws;
    std::vector<std::uint32_t> got(n * k);
    knn(p.data(), 3, n, 3, k, level, ws, got.data());
    EXPECT_EQ(got, ref);
    for (std::size_t i = 0; i < n; ++i) {
      std::set<std::uint32_t> distinct(got.begin() + i * k, got.begin() + (i + 1) * k);
      EXPECT_EQ(distinct.size(), n);
      EXPECT_EQ(got[i * k + k - 1], i);
    }
  }
}

// Non-finite points are rejected by the engine before the network, and the
// kernel promises nothing about their neighbours (one of them makes the
// centre it subtracts non-finite, and then every rank), but it must stay
// safe: every index in range, whatever lanes the padding of a partial last
// panel holds (200 points: the last panel is partly padding).
TEST(Knn, NonFiniteInputGivesIndicesInRange) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (std::size_t dim : {3u, 64u}) {
    const std::size_t n = 200, k = 12;
    auto p = test::random_floats(n * dim, 41);
    for (std::size_t i = 0; i < n; ++i) {
      if (i % 20 != 3) p[i * dim + (i % dim)] = i % 3 == 0 ? nan : (i % 3 == 1 ? inf : -inf);
    }
    for (SimdLevel level : test::supported_levels()) {
      SCOPED_TRACE(std::string(to_string(level)) + " dim " + std::to_string(dim));
      KnnWorkspace ws;
      std::vector<std::uint32_t> got(n * k);
      knn(p.data(), dim, n, dim, k, level, ws, got.data());
      for (std::uint32_t id : got) ASSERT_LT(id, n);
    }
  }
}

TEST(Knn, ATieLargerThanTheCandidateBufferIsRankedOverAllPoints) {
  // One point, then 1100 copies of another: the first row's k-th neighbour
  // ties with more than kKnnTieCandidates points.
  std::vector<float> p = {0.0f, 0.0f, 0.0f};
  for (std::size_t i = 0; i < kKnnTieCandidates + 76; ++i) p.insert(p.end(), {1.0f, 2.0f, 3.0f});
  expect_reference_lists(p, 3, 20);
}

TEST(Knn, AllEqualPointsGiveTheFirstKIndices) {
  for (const auto& [n, dim] : {std::pair<std::size_t, std::size_t>{100, 64}, {kKnnTieCandidates + 76, 3}}) {
    const std::size_t k = 20;
    std::vector<float> p(n * dim, 0.25f);
    for (SimdLevel level : test::supported_levels()) {
      KnnWorkspace ws;
      std::vector<std::uint32_t> got(n * k);
      knn(p.data(), dim, n, dim, k, level, ws, got.data());
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < k; ++j) ASSERT_EQ(got[i * k + j], j) << "n " << n;
      }
    }
  }
}

TEST(Knn, SameResultWithOneAndTwoThreads) {
  const std::size_t n = 2000, k = 20, dim = 64;
  const auto p = test::random_floats(n * dim, 13);
  for (SimdLevel level : test::supported_levels()) {
    KnnWorkspace ws;
    std::vector<std::uint32_t> one(n * k), two(n * k);
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
      knn(p.data(), dim, n, dim, k, level, ws, one.data());
    }
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
      knn(p.data(), dim, n, dim, k, level, ws, two.data());
    }
    EXPECT_EQ(one, two);
  }
}

TEST(Knn, RejectsSizesOutsideItsLimits) {
  std::vector<float> p(30, 0.0f);
  std::vector<std::uint32_t> idx(1000);
  KnnWorkspace ws;
  EXPECT_THROW(knn(p.data(), 3, 10, 3, 0, SimdLevel::Sse42, ws, idx.data()), std::invalid_argument);
  EXPECT_THROW(knn(p.data(), 3, 10, 3, kKnnMaxK + 1, SimdLevel::Sse42, ws, idx.data()), std::invalid_argument);
  EXPECT_THROW(knn(p.data(), 3, 0, 3, 5, SimdLevel::Sse42, ws, idx.data()), std::invalid_argument);
}

}  // namespace
}  // namespace sarmap::kernels
