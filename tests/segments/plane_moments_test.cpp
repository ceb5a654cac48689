#include "engine/segments/plane_moments.hpp"

#include <random>

#include <gtest/gtest.h>

namespace sarmap::segments {
namespace {

TEST(PlaneMoments, FitsAnExactTiltedPlane) {
  const Eigen::Vector3d normal = Eigen::Vector3d(0.2, -0.3, 0.9).normalized();
  const Eigen::Vector3d u = normal.unitOrthogonal();
  const Eigen::Vector3d v = normal.cross(u);
  const Eigen::Vector3d base(3, -2, 1.5);
  PlaneMoments m;
  for (int i = 0; i < 20; ++i) {
    for (int k = 0; k < 15; ++k) m.add(base + u * (0.1 * i) + v * (0.07 * k));
  }
  const PlaneFit fit = fit_plane(m);
  EXPECT_NEAR(std::abs(fit.plane.normal.dot(normal)), 1.0, 1e-12);
  EXPECT_NEAR(fit.plane.distance(base), 0.0, 1e-9);
  EXPECT_NEAR(fit.normal_variance, 0.0, 1e-12);
}

TEST(PlaneMoments, RemoveUndoesAddAndMergeEqualsOneSet) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-5, 5);
  PlaneMoments all, left, right;
  std::vector<Eigen::Vector3d> extra;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(coord(rng), coord(rng), 0.01 * coord(rng));
    all.add(p);
    (i % 2 ? left : right).add(p);
  }
  PlaneMoments merged = left;
  merged += right;
  EXPECT_EQ(merged.count(), all.count());
  EXPECT_TRUE(merged.centroid().isApprox(all.centroid(), 1e-12));
  EXPECT_TRUE(merged.covariance().isApprox(all.covariance(), 1e-10));
  PlaneMoments trimmed = all;
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d p(coord(rng), coord(rng), coord(rng));
    trimmed.add(p);
    extra.push_back(p);
  }
  for (const auto& p : extra) trimmed.remove(p);
  EXPECT_EQ(trimmed.count(), all.count());
  EXPECT_TRUE(trimmed.centroid().isApprox(all.centroid(), 1e-9));
  EXPECT_NEAR((fit_plane(trimmed).plane.normal.cwiseAbs() - fit_plane(all).plane.normal.cwiseAbs()).norm(), 0, 1e-6);
}

TEST(PlaneMoments, RemovingTheLastPointLeavesExactZero) {
  PlaneMoments m;
  m.add({1e3, 2e3, 3e3});
  m.remove({1e3, 2e3, 3e3});
  EXPECT_EQ(m.count(), 0u);
  EXPECT_EQ(m.centroid(), Eigen::Vector3d::Zero());
  EXPECT_EQ(m.covariance(), Eigen::Matrix3d::Zero());
}

}  // namespace
}  // namespace sarmap::segments
