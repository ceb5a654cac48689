// Tests the kNN kernel's visit order (knn.hpp) and the spatial order that
// feeds it (spatial_order.hpp): with any permutation as visit order the lists
// are exactly the reference's, on inputs where the kernel skips most panels
// (points in space, features that are smooth functions of position), on exact
// ties (grid points, blocks padded by repeats, all-equal points), on
// low-dimensional clouds small and large enough to take both ways of testing
// panels, and for 1 and 2 threads; a visit order that is not a permutation is
// refused.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/exact_distance.hpp"
#include "kernels/knn.hpp"
#include "kernels/spatial_order.hpp"
#include "tests/kernels/kernel_test_support.hpp"

namespace sarmap::kernels {
namespace {

struct Cloud {
  std::string name;
  std::vector<float> points;
  std::size_t dim;
  std::vector<float> xyz;  // what the spatial order is computed from
};

std::size_t count_of(const Cloud& c) { return c.points.size() / c.dim; }

// 64-d features that vary smoothly with position, like DGCNN's first layer:
// a fixed random linear map of xyz through tanh, plus a little noise.
std::vector<float> smooth_features(const std::vector<float>& xyz, std::size_t dim, unsigned seed) {
  const auto w = test::random_floats(dim * 3, seed, -3.0f, 3.0f);
  const auto noise = test::random_floats(xyz.size() / 3 * dim, seed + 1, -1e-3f, 1e-3f);
  std::vector<float> f(xyz.size() / 3 * dim);
  for (std::size_t i = 0; i < xyz.size() / 3; ++i) {
    for (std::size_t c = 0; c < dim; ++c) {
      const float v = w[c * 3] * xyz[i * 3] + w[c * 3 + 1] * xyz[i * 3 + 1] + w[c * 3 + 2] * xyz[i * 3 + 2];
      f[i * dim + c] = std::tanh(v) + noise[i * dim + c];
    }
  }
  return f;
}

std::vector<Cloud> clouds() {
  std::vector<Cloud> all;
  const auto xyz = test::random_floats(1500 * 3, 31);
  all.push_back({"random 3-d", xyz, 3, xyz});
  all.push_back({"smooth 64-d features", smooth_features(xyz, 64, 32), 64, xyz});
  all.push_back({"random 64-d", test::random_floats(600 * 64, 33), 64, test::random_floats(600 * 3, 34)});
  // A block of 300 points padded to 2400 by repeats, as block sampling does.
  const auto base = test::random_floats(300 * 3, 35);
  std::vector<float> padded;
  for (int copy = 0; copy < 8; ++copy) padded.insert(padded.end(), base.begin(), base.end());
  all.push_back({"padded by repeats", padded, 3, padded});
  // Integer grid, each point three times: exact ties everywhere.
  std::vector<float> grid;
  for (int copy = 0; copy < 3; ++copy) {
    for (int x = 0; x < 6; ++x) {
      for (int y = 0; y < 5; ++y) {
        for (int z = 0; z < 4; ++z) grid.insert(grid.end(), {float(x), float(y), float(z)});
      }
    }
  }
  all.push_back({"grid with copies", grid, 3, grid});
  all.push_back({"all equal", std::vector<float>(100 * 3, 0.25f), 3, std::vector<float>(100 * 3, 0.25f)});
  const auto few = test::random_floats(7 * 3, 36);
  all.push_back({"fewer than k", few, 3, few});
  return all;
}

std::vector<std::vector<std::uint32_t>> orders_for(const Cloud& c) {
  const std::size_t n = count_of(c);
  std::vector<std::uint32_t> identity(n), shuffled(n), spatial(n);
  std::iota(identity.begin(), identity.end(), 0u);
  shuffled = identity;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(37));
  AlignedBuffer<std::uint64_t> keys;
  spatial_order(c.xyz.data(), 3, n, keys, spatial.data());
  return {identity, shuffled, spatial};
}

TEST(KnnVisitOrder, AnyPermutationGivesTheReferenceLists) {
  const std::size_t k = 20;
  for (const Cloud& c : clouds()) {
    const std::size_t n = count_of(c);
    std::vector<std::uint32_t> ref(n * k);
    knn_reference(c.points.data(), c.dim, n, c.dim, k, ref.data());
    for (const auto& order : orders_for(c)) {
      for (SimdLevel level : test::supported_levels()) {
        KnnWorkspace ws;
        std::vector<std::uint32_t> got(n * k);
        knn(c.points.data(), c.dim, n, c.dim, k, level, ws, got.data(), order.data());
        EXPECT_EQ(got, ref) << c.name << ", " << to_string(level);
      }
    }
  }
}

// The k nearest of row i by the reference's arithmetic: exact distances to
// every point, ties by index.
std::vector<std::uint32_t> reference_row(const std::vector<float>& p, std::size_t dim, std::size_t i, std::size_t k) {
  const std::size_t n = p.size() / dim;
  std::vector<double> d(n);
  for (std::size_t j = 0; j < n; ++j) d[j] = exact_squared_distance(p.data() + i * dim, p.data() + j * dim, dim);
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                    [&](std::uint32_t a, std::uint32_t b) { return d[a] < d[b] || (d[a] == d[b] && a < b); });
  order.resize(k);
  return order;
}

// Low-dimensional points test a tile against every panel at once when there
// are at most kKnnGapsUpFrontMaxPanels panels, and one panel at a time
// beyond: both ways give the reference's lists (checked on sampled rows; the
// full reference is quadratic). 3-d and 2-d clouds of 40,000 points have more
// panels than that at every instruction set, 4,000 fewer.
TEST(KnnVisitOrder, LowDimensionalCloudsOfAnySizeGiveTheReferenceLists) {
  const std::size_t k = 20;
  for (std::size_t dim : {2u, 3u}) {
    for (std::size_t n : {4000u, 40000u}) {
      auto p = test::random_floats(n * dim, 40 + static_cast<unsigned>(dim));
      // Some exact copies, so ties cross panels too.
      for (std::size_t i = 0; i < n / 10; ++i) std::copy_n(p.data() + (i * 7 % n) * dim, dim, p.data() + (n - 1 - i) * dim);
      std::vector<float> xyz(n * 3, 0.0f);
      for (std::size_t i = 0; i < n; ++i) std::copy_n(p.data() + i * dim, dim, xyz.data() + i * 3);
      std::vector<std::uint32_t> order(n);
      AlignedBuffer<std::uint64_t> keys;
      spatial_order(xyz.data(), 3, n, keys, order.data());
      for (SimdLevel level : test::supported_levels()) {
        KnnWorkspace ws;
        std::vector<std::uint32_t> got(n * k);
        knn(p.data(), dim, n, dim, k, level, ws, got.data(), order.data());
        for (std::size_t i = 0; i < n; i += n / 97) {
          const std::vector<std::uint32_t> row(got.begin() + static_cast<std::ptrdiff_t>(i * k),
                                               got.begin() + static_cast<std::ptrdiff_t>((i + 1) * k));
          ASSERT_EQ(row, reference_row(p, dim, i, k)) << dim << "-d, " << n << " points, row " << i << ", "
                                                       << to_string(level);
        }
      }
    }
  }
}

TEST(KnnVisitOrder, OneAndTwoThreadsAgree) {
  const std::size_t k = 16;
  for (const Cloud& c : clouds()) {
    const std::size_t n = count_of(c);
    const auto order = orders_for(c)[2];
    for (SimdLevel level : test::supported_levels()) {
      KnnWorkspace ws;
      std::vector<std::uint32_t> one(n * k), two(n * k);
      {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        knn(c.points.data(), c.dim, n, c.dim, k, level, ws, one.data(), order.data());
      }
      {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        knn(c.points.data(), c.dim, n, c.dim, k, level, ws, two.data(), order.data());
      }
      EXPECT_EQ(one, two) << c.name << ", " << to_string(level);
    }
  }
}

TEST(KnnVisitOrder, ANonPermutationIsRefused) {
  const std::size_t n = 50, k = 4;
  const auto p = test::random_floats(n * 3, 38);
  std::vector<std::uint32_t> idx(n * k), order(n);
  std::iota(order.begin(), order.end(), 0u);
  KnnWorkspace ws;
  order[7] = 3;  // 3 twice, 7 never
  EXPECT_THROW(knn(p.data(), 3, n, 3, k, SimdLevel::Sse42, ws, idx.data(), order.data()), std::invalid_argument);
  order[7] = static_cast<std::uint32_t>(n);  // past the points
  EXPECT_THROW(knn(p.data(), 3, n, 3, k, SimdLevel::Sse42, ws, idx.data(), order.data()), std::invalid_argument);
}

bool is_permutation_of_indices(const std::vector<std::uint32_t>& order) {
  std::vector<std::uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    if (sorted[i] != i) return false;
  }
  return true;
}

TEST(SpatialOrder, FollowsAHilbertCurve) {
  // A 4 x 4 x 4 grid, listed in a scrambled order, plus one point that
  // stretches the box so that the grid's cells are 256 apart of the 1024 per
  // axis (1023 / 3.99609375 = 256 exactly): along a Hilbert curve every step
  // between grid points moves one cell along one axis (a Morton curve jumps).
  const float stretch = 1023.0f / 256.0f;
  std::vector<float> p;
  std::vector<std::array<int, 3>> cell;
  for (int n = 0; n < 64; ++n) {
    const int m = (n * 37) % 64;  // 37 is coprime to 64: a permutation
    cell.push_back({m & 3, (m >> 2) & 3, m >> 4});
    p.insert(p.end(), {float(m & 3), float((m >> 2) & 3), float(m >> 4)});
  }
  p.insert(p.end(), {stretch, stretch, stretch});
  std::vector<std::uint32_t> order(65);
  AlignedBuffer<std::uint64_t> keys;
  spatial_order(p.data(), 3, 65, keys, order.data());
  ASSERT_TRUE(is_permutation_of_indices(order));
  std::vector<std::array<int, 3>> path;
  for (std::uint32_t i : order) {
    if (i < 64) path.push_back(cell[i]);
  }
  EXPECT_EQ(path.front(), (std::array<int, 3>{0, 0, 0}));
  for (std::size_t s = 1; s < path.size(); ++s) {
    int moved = 0;
    for (int a = 0; a < 3; ++a) moved += std::abs(path[s][a] - path[s - 1][a]);
    EXPECT_EQ(moved, 1) << "step " << s;
  }
}

TEST(SpatialOrder, KeepsNeighboursTogether) {
  // Two clusters far apart, interleaved in the input: the order lists one
  // cluster, then the other.
  const std::size_t n = 200;
  std::vector<float> p(n * 4);
  const auto jitter = test::random_floats(n * 3, 39, 0.0f, 0.1f);
  for (std::size_t i = 0; i < n; ++i) {
    const float offset = i % 2 == 0 ? 0.0f : 10.0f;
    for (int a = 0; a < 3; ++a) p[i * 4 + a] = offset + jitter[i * 3 + a];
    p[i * 4 + 3] = 123.0f;  // a fourth channel the order ignores
  }
  std::vector<std::uint32_t> order(n);
  AlignedBuffer<std::uint64_t> keys;
  spatial_order(p.data(), 4, n, keys, order.data());
  ASSERT_TRUE(is_permutation_of_indices(order));
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(order[i] % 2, i < n / 2 ? 0u : 1u) << i;
}

TEST(SpatialOrder, EqualAndNonFinitePointsGiveAPermutation) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::vector<float> p = {1, 1, 1, nan, 0, 0, 1, 1, 1, inf, -inf, 2, 1, 1, 1, 0, 0, 0};
  std::vector<std::uint32_t> order(6);
  AlignedBuffer<std::uint64_t> keys;
  spatial_order(p.data(), 3, 6, keys, order.data());
  ASSERT_TRUE(is_permutation_of_indices(order));
  // The three equal points keep their index order.
  std::vector<std::uint32_t> equal;
  for (std::uint32_t i : order) {
    if (i == 0 || i == 2 || i == 4) equal.push_back(i);
  }
  EXPECT_EQ(equal, (std::vector<std::uint32_t>{0, 2, 4}));
  // Equal points everywhere: every axis without extent.
  std::vector<float> same(5 * 3, 2.5f);
  std::vector<std::uint32_t> same_order(5);
  spatial_order(same.data(), 3, 5, keys, same_order.data());
  EXPECT_EQ(same_order, (std::vector<std::uint32_t>{0, 1, 2, 3, 4}));
}

}  // namespace
}  // namespace sarmap::kernels
