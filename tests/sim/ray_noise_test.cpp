// Tests of engine/sim/ray_noise.hpp: the counter-based draws have the right
// distributions and depend only on (seed, frame, ray).
#include "engine/sim/ray_noise.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace sarmap::sim {
namespace {

TEST(RayNoise, KinectSigmaFollowsTheQuadraticModel) {
  EXPECT_DOUBLE_EQ(kinect_sigma(0.4), 0.0012);
  EXPECT_NEAR(kinect_sigma(3.4), 0.0012 + 0.0019 * 9.0, 1e-15);
}

TEST(RayNoise, KeysSeparateSeedFrameAndRay) {
  EXPECT_EQ(ray_key(1, 2, 3), ray_key(1, 2, 3));
  EXPECT_NE(ray_key(1, 2, 3), ray_key(2, 2, 3));
  EXPECT_NE(ray_key(1, 2, 3), ray_key(1, 3, 3));
  EXPECT_NE(ray_key(1, 2, 3), ray_key(1, 2, 4));
  EXPECT_NE(ray_key(1, 2, 3), ray_key(1, 3, 2));
}

TEST(RayNoise, DrawsHaveTheirDistributions) {
  constexpr int kN = 200000;
  double sum = 0, sum2 = 0, usum = 0;
  int dropped = 0;
  const NoiseSpec noise{NoiseKind::Gaussian, 0.02, 0.2};
  double noise_sum2 = 0;
  int kept = 0;
  for (int i = 0; i < kN; ++i) {
    const std::uint64_t key = ray_key(9, 1, static_cast<std::uint64_t>(i));
    const double z = standard_normal(key);
    sum += z;
    sum2 += z * z;
    const double u = uniform01(key, 5);
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    usum += u;
    double m = 0;
    if (apply_noise(noise, 2.0, key, m)) {
      ++kept;
      noise_sum2 += (m - 2.0) * (m - 2.0);
    } else {
      ++dropped;
    }
  }
  EXPECT_NEAR(sum / kN, 0.0, 0.01);
  EXPECT_NEAR(std::sqrt(sum2 / kN), 1.0, 0.01);
  EXPECT_NEAR(usum / kN, 0.5, 0.005);
  EXPECT_NEAR(static_cast<double>(dropped) / kN, 0.2, 0.005);
  EXPECT_NEAR(std::sqrt(noise_sum2 / kept), 0.02, 0.0005);
  double exact = 0;
  EXPECT_TRUE(apply_noise(NoiseSpec{}, 1.5, 7, exact));
  EXPECT_EQ(exact, 1.5);
}

}  // namespace
}  // namespace sarmap::sim
