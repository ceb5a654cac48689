// Tests kernels/edge_conv.hpp against its scalar references at every
// instruction set: standard and odd channel counts, k = 1, all-equal
// features, random neighbour lists with repeats, and 1 vs 2 threads.
#include "kernels/edge_conv.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <random>
#include <vector>

#include "tests/kernels/kernel_test_support.hpp"

namespace sarmap::kernels {
namespace {

std::vector<std::uint32_t> random_idx(std::size_t n, std::size_t k, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::uint32_t> dist(0, static_cast<std::uint32_t>(n - 1));
  std::vector<std::uint32_t> idx(n * k);
  for (auto& i : idx) i = dist(rng);
  return idx;
}

struct Case {
  std::size_t n, hidden, out, k;
};

TEST(EdgeConv, MatchesReference) {
  const Case cases[] = {{200, 64, 64, 20}, {57, 13, 37, 5}, {10, 64, 64, 1}, {33, 8, 100, 64}, {90, 100, 16, 3}};
  for (SimdLevel level : test::supported_levels()) {
    for (const Case& c : cases) {
      const std::size_t ld = c.hidden + 2, ldo = c.out + 1;
      const auto a = test::random_floats(c.n * ld, 1), b = test::random_floats(c.n * ld, 2);
      const auto w = test::random_floats(c.out * c.hidden, 3), bias = test::random_floats(c.out, 4);
      const auto idx = random_idx(c.n, c.k, 5);
      std::vector<float> got(c.n * ldo, 7.0f), ref(c.n * ldo, 7.0f);
      edge_conv_max(a.data(), b.data(), ld, c.n, c.hidden, idx.data(), c.k, 0.2f,
                    PackedMatrix(w.data(), bias.data(), c.out, c.hidden, level), 0.2f, got.data(), ldo);
      edge_conv_max_reference(a.data(), b.data(), ld, c.n, c.hidden, idx.data(), c.k, 0.2f, w.data(), bias.data(),
                              c.out, 0.2f, ref.data(), ldo);
      for (std::size_t i = 0; i < got.size(); ++i) {
        ASSERT_NEAR(got[i], ref[i], 1e-5 * c.hidden) << to_string(level) << " n=" << c.n << " at " << i;
      }
    }
  }
}

TEST(EdgeConv, AllEqualFeaturesGiveOneValuePerChannel) {
  const std::size_t n = 40, hidden = 64, out = 64, k = 20;
  std::vector<float> a(n * hidden, 0.3f), b(n * hidden, -0.1f);
  const auto w = test::random_floats(out * hidden, 6);
  const auto idx = random_idx(n, k, 7);
  for (SimdLevel level : test::supported_levels()) {
    std::vector<float> got(n * out);
    edge_conv_max(a.data(), b.data(), hidden, n, hidden, idx.data(), k, 0.2f,
                  PackedMatrix(w.data(), nullptr, out, hidden, level), 0.2f, got.data(), out);
    for (std::size_t i = 1; i < n; ++i) {
      for (std::size_t o = 0; o < out; ++o) ASSERT_EQ(got[i * out + o], got[o]);
    }
  }
}

TEST(GatherMax, MatchesReference) {
  const Case cases[] = {{300, 64, 0, 20}, {31, 7, 0, 4}, {5, 64, 0, 1}};
  for (SimdLevel level : test::supported_levels()) {
    for (const Case& c : cases) {
      const std::size_t ld = c.hidden * 2;  // a and b interleaved as the model stores them
      const auto ab = test::random_floats(c.n * ld, 8);
      const auto idx = random_idx(c.n, c.k, 9);
      std::vector<float> got(c.n * c.hidden), ref(c.n * c.hidden);
      gather_max(ab.data(), ab.data() + c.hidden, ld, c.n, c.hidden, idx.data(), c.k, 0.2f, level, got.data(),
                 c.hidden);
      gather_max_reference(ab.data(), ab.data() + c.hidden, ld, c.n, c.hidden, idx.data(), c.k, 0.2f, ref.data(),
                           c.hidden);
      EXPECT_EQ(got, ref) << to_string(level);  // max and one add: exact
    }
  }
}

TEST(EdgeConv, SameResultWithOneAndTwoThreads) {
  const std::size_t n = 1000, hidden = 64, out = 64, k = 20;
  const auto a = test::random_floats(n * hidden, 10), b = test::random_floats(n * hidden, 11);
  const auto w = test::random_floats(out * hidden, 12);
  const auto idx = random_idx(n, k, 13);
  for (SimdLevel level : test::supported_levels()) {
    const PackedMatrix packed(w.data(), nullptr, out, hidden, level);
    std::vector<float> one(n * out), two(n * out);
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
      edge_conv_max(a.data(), b.data(), hidden, n, hidden, idx.data(), k, 0.2f, packed, 0.2f, one.data(), out);
    }
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
      edge_conv_max(a.data(), b.data(), hidden, n, hidden, idx.data(), k, 0.2f, packed, 0.2f, two.data(), out);
    }
    EXPECT_EQ(one, two);
  }
}

TEST(EdgeConv, RejectsSizesOutsideItsLimits) {
  std::vector<float> w(64 * (kEdgeMaxHidden + 1));
  const PackedMatrix wide(w.data(), nullptr, 64, kEdgeMaxHidden + 1, SimdLevel::Sse42);
  std::vector<float> x(10);
  std::vector<std::uint32_t> idx(10);
  EXPECT_THROW(edge_conv_max(x.data(), x.data(), 1, 1, kEdgeMaxHidden + 1, idx.data(), 1, 0.2f, wide, 0.2f,
                             x.data(), 1),
               std::invalid_argument);
}

}  // namespace
}  // namespace sarmap::kernels
