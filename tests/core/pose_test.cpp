#include "engine/core/pose.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <limits>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/point_buffer.hpp"

namespace sarmap {
namespace {

TEST(Pose, FromQuaternionRotatesAndTranslates) {
  // 90 degrees about z.
  const double s = std::sqrt(0.5);
  const Pose pose = Pose::from_quaternion(0, 0, s, s, Eigen::Vector3d(1, 2, 3));
  const Eigen::Vector3d p = pose * Eigen::Vector3d(1, 0, 0);
  EXPECT_NEAR(p.x(), 1.0, 1e-12);
  EXPECT_NEAR(p.y(), 3.0, 1e-12);
  EXPECT_NEAR(p.z(), 3.0, 1e-12);
}

TEST(Pose, MatrixRoundTripAndInverse) {
  const Pose pose = Pose::from_quaternion(0.1, -0.2, 0.3, 0.9, Eigen::Vector3d(-4, 5, 0.5));
  const Pose again = Pose::from_matrix(pose.matrix());
  EXPECT_TRUE(again.matrix().isApprox(pose.matrix(), 1e-12));
  const Pose identity = pose * pose.inverse();
  EXPECT_TRUE(identity.matrix().isApprox(Eigen::Matrix4d::Identity(), 1e-12));
}

TEST(Pose, RejectsNonOrthonormalRotation) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 0) = 1.01;
  EXPECT_THROW(Pose::from_matrix(m), Error);
  m(0, 0) = 1.0004;  // |R^T R - I| = 8e-4, within the 1e-3 tolerance
  EXPECT_NO_THROW(Pose::from_matrix(m));
}

TEST(Pose, RejectsReflectionNaNAndBadLastRow) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(2, 2) = -1;
  EXPECT_THROW(Pose::from_matrix(m), Error);
  m = Eigen::Matrix4d::Identity();
  m(1, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Pose::from_matrix(m), Error);
  m = Eigen::Matrix4d::Identity();
  m(3, 0) = 1;
  EXPECT_THROW(Pose::from_matrix(m), Error);
  EXPECT_THROW(Pose::from_quaternion(0, 0, 0, 0, Eigen::Vector3d::Zero()), Error);
}

TEST(Pose, ErrorNamesTheSource) {
  std::vector<double> v(16, 0.0);
  try {
    Pose::from_row_major(v, "frames[3].pose");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frames[3].pose"), std::string::npos);
    EXPECT_EQ(e.code(), ErrorCode::InvalidData);
  }
  EXPECT_THROW(Pose::from_row_major(std::vector<double>(12, 0.0)), Error);
}

TEST(Pose, AppliesToPointsAndNormals) {
  PointBuffer points;
  points.enable_normals();
  points.push_back(1, 0, 0);
  points.normal_x()[0] = 1;
  const double s = std::sqrt(0.5);
  Pose::from_quaternion(0, 0, s, s, Eigen::Vector3d(0, 0, 1)).apply(points);
  EXPECT_NEAR(points.x()[0], 0.0f, 1e-6);
  EXPECT_NEAR(points.y()[0], 1.0f, 1e-6);
  EXPECT_NEAR(points.z()[0], 1.0f, 1e-6);
  EXPECT_NEAR(points.normal_y()[0], 1.0f, 1e-6);
  EXPECT_NEAR(points.normal_z()[0], 0.0f, 1e-6);
}

}  // namespace
}  // namespace sarmap
