#include "engine/segments/ransac_plane.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "engine/core/error.hpp"

namespace sarmap::segments {
namespace {

struct Cloud {
  std::vector<float> x, y, z;
  PlanePoints view() const { return {x, y, z}; }
  void add(const Eigen::Vector3d& p) {
    x.push_back(static_cast<float>(p.x()));
    y.push_back(static_cast<float>(p.y()));
    z.push_back(static_cast<float>(p.z()));
  }
};

// 2,000 points on an exact tilted plane and `outliers` of the total spread through the box around it.
Cloud plane_with_outliers(const Eigen::Vector3d& normal, double offset, double outlier_share, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-2, 2);
  const Eigen::Vector3d a = normal.unitOrthogonal(), b = normal.cross(a);
  Cloud c;
  const int inliers = 2000;
  const int outliers = static_cast<int>(inliers * outlier_share / (1 - outlier_share));
  for (int i = 0; i < inliers; ++i) c.add(-offset * normal + u(rng) * a + u(rng) * b);
  for (int i = 0; i < outliers; ++i) c.add(Eigen::Vector3d(u(rng), u(rng), u(rng)));
  return c;
}

TEST(Ransac, FindsAnExactPlaneAmongThirtyPercentOutliers) {
  const Eigen::Vector3d normal = Eigen::Vector3d(0.1, 0.25, 1).normalized();
  const Cloud c = plane_with_outliers(normal, -0.4, 0.3, 7);
  RansacOptions o;
  o.min_inliers = 100;
  const RansacResult r = find_plane(c.view(), o);
  ASSERT_TRUE(r.found);
  EXPECT_GE(r.inliers, 2000u);            // every plane point, plus outliers that happen to lie near it
  EXPECT_LT(r.inliers, 2000u + 2000u / 20);
  EXPECT_GT(std::abs(r.plane.normal.dot(normal)), std::cos(2.0 * std::numbers::pi / 180));
  EXPECT_LT(std::abs(std::abs(r.plane.offset) - 0.4), 0.02);
  // A sample from the plane ends the search long before the cap.
  EXPECT_LT(r.iterations, o.max_iterations);
}

TEST(Ransac, SameSeedSameAnswerOnOneAndTwoThreads) {
  const Cloud c = plane_with_outliers(Eigen::Vector3d::UnitZ(), 0.0, 0.5, 11);
  RansacOptions o;
  o.seed = 42;
  RansacResult one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = find_plane(c.view(), o);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = find_plane(c.view(), o);
  }
  EXPECT_EQ(one.inliers, two.inliers);
  EXPECT_EQ(one.iterations, two.iterations);
  EXPECT_EQ(one.plane.normal, two.plane.normal);
  EXPECT_EQ(one.plane.offset, two.plane.offset);
  o.seed = 43;
  const RansacResult other = find_plane(c.view(), o);
  EXPECT_TRUE(other.found);  // a different seed draws other samples but finds the plane too
}

TEST(Ransac, IterationsFollowTheConfidenceFormula) {
  EXPECT_EQ(ransac_iterations(1.0, 0.99, 1000), 1u);
  EXPECT_EQ(ransac_iterations(0.5, 0.99, 1000), 35u);  // log(0.01) / log(1 - 0.125) = 34.5
  EXPECT_EQ(ransac_iterations(0.1, 0.99, 1000), 1000u);
  EXPECT_EQ(ransac_iterations(0.0, 0.99, 77), 77u);
}

TEST(Ransac, TooFewPointsOrNoPlaneIsNotFound) {
  Cloud c;
  c.add({0, 0, 0});
  c.add({1, 0, 0});
  EXPECT_FALSE(find_plane(c.view(), {}).found);
  Cloud line;
  for (int i = 0; i < 50; ++i) line.add({0.1 * i, 0, 0});
  EXPECT_FALSE(find_plane(line.view(), {}).found);  // every sample is collinear
}

TEST(Ransac, BadSettingsAndNonFinitePointsAreClearErrors) {
  Cloud c = plane_with_outliers(Eigen::Vector3d::UnitZ(), 0, 0, 1);
  RansacOptions o;
  o.threshold = 0;
  EXPECT_THROW(find_plane(c.view(), o), Error);
  o.threshold = std::nan("");
  EXPECT_THROW(find_plane(c.view(), o), Error);
  o.threshold = 0.02;
  o.confidence = 1.0;
  EXPECT_THROW(find_plane(c.view(), o), Error);
  c.z[17] = std::nanf("");
  try {
    find_plane(c.view(), {});
    FAIL() << "NaN accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 17"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sarmap::segments
