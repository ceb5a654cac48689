// The exact DDA against hand-worked cases (axes, edges, corners, zero length)
// and against a brute-force reference that clips the segment to every voxel
// of its bounding box.
#include "engine/metric/voxel_ray.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace sarmap::metric {
namespace {

std::vector<VoxelKey> walk(std::array<double, 3> a, std::array<double, 3> b) {
  std::vector<VoxelKey> out;
  walk_ray(a.data(), b.data(), [&](const VoxelKey& k) {
    out.push_back(k);
    return true;
  });
  return out;
}

// Length of the segment a->b inside voxel k (Liang-Barsky clipping), in voxel units.
double length_inside(const std::array<double, 3>& a, const std::array<double, 3>& b, const VoxelKey& k) {
  double t0 = 0, t1 = 1;
  const int c[3] = {k.x, k.y, k.z};
  for (int i = 0; i < 3; ++i) {
    const double d = b[i] - a[i];
    if (d == 0) {
      if (a[i] < c[i] || a[i] >= c[i] + 1) return 0;
      continue;
    }
    double ta = (c[i] - a[i]) / d, tb = (c[i] + 1 - a[i]) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t1 <= t0) return 0;
  double len2 = 0;
  for (int i = 0; i < 3; ++i) len2 += (b[i] - a[i]) * (b[i] - a[i]);
  return (t1 - t0) * std::sqrt(len2);
}

TEST(VoxelRay, AlongEachAxisBothDirections) {
  const auto px = walk({0.5, 0.5, 0.5}, {5.5, 0.5, 0.5});
  ASSERT_EQ(px.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(px[i], (VoxelKey{i, 0, 0}));
  const auto ny = walk({0.5, 0.5, 0.5}, {0.5, -3.2, 0.5});
  ASSERT_EQ(ny.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(ny[i], (VoxelKey{0, -i, 0}));
  const auto pz = walk({-0.5, -0.5, -2.5}, {-0.5, -0.5, 1.5});
  ASSERT_EQ(pz.size(), 4u);
  EXPECT_EQ(pz.front(), (VoxelKey{-1, -1, -3}));
  EXPECT_EQ(pz.back(), (VoxelKey{-1, -1, 0}));
}

TEST(VoxelRay, ThroughCornersStepsAllAxesTogether) {
  const auto r = walk({0.5, 0.5, 0.5}, {3.5, 3.5, 3.5});
  ASSERT_EQ(r.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(r[i], (VoxelKey{i, i, i}));
  const auto back = walk({3.5, 3.5, 3.5}, {0.5, 0.5, 0.5});
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[2], (VoxelKey{1, 1, 1}));
}

TEST(VoxelRay, ThroughEdgesStepsBothAxes) {
  const auto r = walk({0.5, 0.5, 0.2}, {2.5, 2.5, 0.7});
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0], (VoxelKey{0, 0, 0}));
  EXPECT_EQ(r[1], (VoxelKey{1, 1, 0}));
  // At 0.05 m resolution, a diagonal between voxel centres in metres.
  const double inv = 1.0 / 0.05;
  const auto m = walk({0.025 * inv, 0.025 * inv, 0.1 * inv}, {0.175 * inv, -0.125 * inv, 0.1 * inv});
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[1], (VoxelKey{1, -1, 2}));
}

TEST(VoxelRay, ZeroLengthAndSameVoxelVisitNothing) {
  EXPECT_TRUE(walk({1.5, 2.5, 3.5}, {1.5, 2.5, 3.5}).empty());
  EXPECT_TRUE(walk({1.1, 2.2, 3.3}, {1.9, 2.8, 3.01}).empty());
}

TEST(VoxelRay, EndOnAFaceBelongsToTheUpperVoxel) {
  const auto r = walk({0.5, 0.5, 0.5}, {3.0, 0.5, 0.5});
  ASSERT_EQ(r.size(), 3u);  // 0, 1, 2; the end voxel is 3
  EXPECT_EQ(r.back(), (VoxelKey{2, 0, 0}));
}

TEST(VoxelRay, StopsWhenTheVisitorSaysSo) {
  int seen = 0;
  const double a[3] = {0.5, 0.5, 0.5}, b[3] = {20.5, 0.5, 0.5};
  const std::size_t n = walk_ray(a, b, [&](const VoxelKey&) { return ++seen < 4; });
  EXPECT_EQ(n, 4u);
  EXPECT_EQ(seen, 4);
}

TEST(VoxelRay, MatchesBruteForceClippingOnRandomSegments) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-12.0, 12.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const std::array<double, 3> a{coord(rng), coord(rng), coord(rng)};
    const std::array<double, 3> b{coord(rng), coord(rng), coord(rng)};
    const auto got = walk(a, b);
    const VoxelKey end{int(std::floor(b[0])), int(std::floor(b[1])), int(std::floor(b[2]))};
    // Every voxel of the bounding box the segment passes through, minus the end voxel.
    std::vector<std::pair<double, VoxelKey>> expected;
    for (int z = int(std::floor(std::min(a[2], b[2]))); z <= int(std::floor(std::max(a[2], b[2]))); ++z)
      for (int y = int(std::floor(std::min(a[1], b[1]))); y <= int(std::floor(std::max(a[1], b[1]))); ++y)
        for (int x = int(std::floor(std::min(a[0], b[0]))); x <= int(std::floor(std::max(a[0], b[0]))); ++x) {
          const VoxelKey k{x, y, z};
          if (k == end || length_inside(a, b, k) <= 1e-9) continue;
          // Order along the ray: distance of the voxel centre projected on the segment.
          const double t = (x + 0.5 - a[0]) * (b[0] - a[0]) + (y + 0.5 - a[1]) * (b[1] - a[1]) +
                           (z + 0.5 - a[2]) * (b[2] - a[2]);
          expected.push_back({t, k});
        }
    ASSERT_EQ(got.size(), expected.size()) << "trial " << trial;
    auto sorted_got = got;
    auto by_key = [](const VoxelKey& p, const VoxelKey& q) {
      return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
    };
    std::vector<VoxelKey> keys;
    for (auto& e : expected) keys.push_back(e.second);
    std::sort(sorted_got.begin(), sorted_got.end(), by_key);
    std::sort(keys.begin(), keys.end(), by_key);
    EXPECT_EQ(sorted_got, keys) << "trial " << trial;
    // Consecutive voxels share a face (no ties in random data): 6-connected.
    for (std::size_t i = 1; i < got.size(); ++i) {
      const int step = std::abs(got[i].x - got[i - 1].x) + std::abs(got[i].y - got[i - 1].y) +
                       std::abs(got[i].z - got[i - 1].z);
      EXPECT_EQ(step, 1);
    }
  }
}

TEST(VoxelRay, LongRayFarFromTheOriginEndsExactly) {
  // 10 km at 0.01 m is 1e6 voxels; a ray there still ends in its end voxel.
  // It crosses 800 + 400 + 288 faces; two of them (x at parameter
  // 0.0558331, y at 0.0558338) are 6.3e-7 of the length apart, closer than
  // the tie tolerance (2^-20 = 9.5e-7), so the walk steps them together:
  // one voxel fewer than crossings.
  const double a[3] = {999000.3, -999000.7, 12.5}, b[3] = {999800.9, -999400.1, 300.2};
  VoxelKey last{};
  const std::size_t n = walk_ray(a, b, [&](const VoxelKey& k) {
    last = k;
    return true;
  });
  EXPECT_EQ(n, std::size_t(800 + 400 + 288 - 1));
  EXPECT_EQ(std::abs(last.x - 999800) + std::abs(last.y + 999401) + std::abs(last.z - 300), 1);
}

TEST(VoxelRay, CrossingsJustBeyondTheTieToleranceStepApart) {
  // From (0.5, 0.5) to (1.5, 1.5 + 2 g) in the plane z = 0.5: the faces
  // x = 1 and y = 1 are crossed at parameters 0.5 and 0.5 / (1 + 2 g), g
  // apart to first order. 4 x the tolerance apart: two steps, through
  // (0, 1) first (y crosses earlier); a tenth of it: one diagonal step,
  // straight into the end voxel (1, 1).
  const auto apart = walk({0.5, 0.5, 0.5}, {1.5, 1.5 + 8.0 * kRayTieParameter, 0.5});
  ASSERT_EQ(apart.size(), 2u);
  EXPECT_EQ(apart[1], (VoxelKey{0, 1, 0}));
  EXPECT_EQ(walk({0.5, 0.5, 0.5}, {1.5, 1.5 + 0.2 * kRayTieParameter, 0.5}).size(), 1u);
}

TEST(VoxelRay, StartFractionsThatRoundToOneAndEndsJustBelowAFace) {
  // 0.99999999999 rounds to 1.0 in float, as does an end on the face at 1:
  // dda_setup keeps the start below 1, so the step to cell 1 has a finite
  // crossing (else 0 x infinity, a NaN that never steps).
  const auto up = walk({0.99999999999, 0.5, 0.5}, {1.0, 0.5, 0.5});
  ASSERT_EQ(up.size(), 1u);
  EXPECT_EQ(up.front(), (VoxelKey{0, 0, 0}));
  // An end 1e-50 below the face at 0 lies in cell -1, but rounds to -0 in
  // float; dda_setup keeps it below 0: one step, visiting cell 0 only.
  const auto down = walk({0.5, 0.5, 0.5}, {-1e-50, 0.5, 0.5});
  ASSERT_EQ(down.size(), 1u);
  EXPECT_EQ(down.front(), (VoxelKey{0, 0, 0}));
  // Both, on every axis, along the diagonal and back.
  EXPECT_EQ(walk({0.99999999999, 0.99999999999, 0.99999999999}, {1.0, 1.0, 1.0}).size(), 1u);
  EXPECT_EQ(walk({0.0, 0.0, 0.0}, {-1e-50, -1e-50, -1e-50}).size(), 1u);
}

}  // namespace
}  // namespace sarmap::metric
