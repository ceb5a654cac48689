// The voxel-key kernel at every instruction set against the reference, and
// the reference against the definition (floor of coordinate / resolution per
// axis, unpacked): random points at several resolutions, points exactly on
// voxel faces and at +-0, the limits themselves and just beyond, NaN and
// infinities, and counts that leave a tail shorter than a vector.
#include "kernels/voxel_keys.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "tests/kernels/kernel_test_support.hpp"

namespace sarmap::kernels {
namespace {

constexpr double kLimit = 10000.0;

struct Points {
  std::vector<float> x, y, z;
  void add(float a, float b, float c) {
    x.push_back(a);
    y.push_back(b);
    z.push_back(c);
  }
  std::size_t size() const { return x.size(); }
};

std::int64_t unpacked(std::uint64_t key, int axis) {
  return static_cast<std::int64_t>((key >> (kVoxelKeyBits * axis)) & kVoxelKeyMask) - kVoxelKeyOffset;
}

Points awkward_points(double resolution) {
  Points p;
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const auto res = static_cast<float>(resolution);
  for (float v : {0.0f, -0.0f, res, -res, 3 * res, -3 * res, 0.5f * res, -0.5f * res, 1e-30f, -1e-30f}) {
    p.add(v, -v, v);
  }
  for (float v : {10000.0f, -10000.0f, std::nextafter(10000.0f, 2e4f), std::nextafter(-10000.0f, -2e4f)}) {
    p.add(v, 0.0f, 0.0f);
    p.add(0.0f, v, 0.0f);
    p.add(0.0f, 0.0f, v);
  }
  for (float v : {inf, -inf, nan}) {
    p.add(v, 1.0f, 1.0f);
    p.add(1.0f, v, 1.0f);
    p.add(1.0f, 1.0f, v);
  }
  return p;
}

Points random_points(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> near(-20.0f, 20.0f), far(-10000.0f, 10000.0f);
  Points p;
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 5 == 0) {
      p.add(far(rng), far(rng), far(rng));
    } else {
      p.add(near(rng), near(rng), near(rng));
    }
  }
  return p;
}

std::vector<std::uint64_t> keys_at(const Points& p, double resolution, SimdLevel level) {
  std::vector<std::uint64_t> keys(p.size(), 0);
  voxel_keys(p.x.data(), p.y.data(), p.z.data(), p.size(), 1.0 / resolution, kLimit, keys.data(), level);
  return keys;
}

TEST(VoxelKeys, ReferenceIsTheFloorOfEachCoordinatePacked) {
  for (double resolution : {0.01, 0.025, 0.05, 0.3}) {
    Points p = random_points(500, 7);
    const Points awkward = awkward_points(resolution);
    for (std::size_t i = 0; i < awkward.size(); ++i) p.add(awkward.x[i], awkward.y[i], awkward.z[i]);
    std::vector<std::uint64_t> keys(p.size());
    voxel_keys_reference(p.x.data(), p.y.data(), p.z.data(), p.size(), 1.0 / resolution, kLimit, keys.data());
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double c[3] = {p.x[i], p.y[i], p.z[i]};
      const bool inside = std::fabs(c[0]) <= kLimit && std::fabs(c[1]) <= kLimit && std::fabs(c[2]) <= kLimit;
      if (!inside) {
        EXPECT_EQ(keys[i], kRejectedVoxelKey) << "point " << i;
        continue;
      }
      ASSERT_NE(keys[i], kRejectedVoxelKey) << "point " << i;
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(unpacked(keys[i], a), static_cast<std::int64_t>(std::floor(c[a] * (1.0 / resolution))))
            << "point " << i << " axis " << a << " at " << resolution;
      }
    }
  }
}

TEST(VoxelKeys, EveryLevelMatchesTheReference) {
  for (double resolution : {0.01, 0.05, 0.3}) {
    // 1000 random points and the awkward ones, at every count up to 40 so
    // that every tail length of every vector width is exercised.
    Points p = random_points(1000, 11);
    const Points awkward = awkward_points(resolution);
    for (std::size_t i = 0; i < awkward.size(); ++i) p.add(awkward.x[i], awkward.y[i], awkward.z[i]);
    std::vector<std::uint64_t> expected(p.size());
    voxel_keys_reference(p.x.data(), p.y.data(), p.z.data(), p.size(), 1.0 / resolution, kLimit,
                         expected.data());
    for (SimdLevel level : test::supported_levels()) {
      EXPECT_EQ(keys_at(p, resolution, level), expected) << to_string(level) << " at " << resolution;
      for (std::size_t n = 0; n <= 40; ++n) {
        // The awkward points lead, so short counts hold them too.
        std::vector<std::uint64_t> keys(n + 1, 12345);
        voxel_keys(awkward.x.data(), awkward.y.data(), awkward.z.data(), std::min(n, awkward.size()),
                   1.0 / resolution, kLimit, keys.data(), level);
        for (std::size_t i = 0; i < std::min(n, awkward.size()); ++i) {
          std::uint64_t one = 0;
          voxel_keys_reference(&awkward.x[i], &awkward.y[i], &awkward.z[i], 1, 1.0 / resolution, kLimit, &one);
          ASSERT_EQ(keys[i], one) << to_string(level) << " count " << n << " point " << i;
        }
        EXPECT_EQ(keys[std::min(n, awkward.size())], 12345u) << "wrote past the count at " << n;
      }
    }
  }
}

}  // namespace
}  // namespace sarmap::kernels
