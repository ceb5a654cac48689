// A rigid transform that maps a sensor frame to the world frame (z up).
//
// Frames: a depth camera's points are in its optical frame (x right, y down,
// z forward); a LiDAR's in its body frame (x forward, z up). A pose's rotation
// must be orthonormal within 1e-3 with determinant +1; anything else is an
// error rather than a silently skewed map.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <span>
#include <string_view>

namespace sarmap {

class PointBuffer;

class Pose {
 public:
  // Identity.
  Pose() = default;
  // Validates the rotation; `what` names the source in the error message.
  Pose(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation,
       std::string_view what = "pose");

  // From a 4x4 homogeneous matrix; the last row must be [0 0 0 1].
  static Pose from_matrix(const Eigen::Matrix4d& matrix, std::string_view what = "pose");
  // From 16 numbers, row-major.
  static Pose from_row_major(std::span<const double> values, std::string_view what = "pose");
  // From a unit quaternion (normalised here; a zero or non-finite one is an error).
  static Pose from_quaternion(double qx, double qy, double qz, double qw,
                              const Eigen::Vector3d& translation,
                              std::string_view what = "pose");

  const Eigen::Matrix3d& rotation() const { return rotation_; }
  const Eigen::Vector3d& translation() const { return translation_; }
  Eigen::Matrix4d matrix() const;
  Eigen::Quaterniond quaternion() const { return Eigen::Quaterniond(rotation_); }

  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return rotation_ * p + translation_; }
  Pose operator*(const Pose& other) const;
  Pose inverse() const;

  // Moves every point of the buffer by this pose (and rotates its normals).
  void apply(PointBuffer& points) const;

 private:
  Eigen::Matrix3d rotation_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation_ = Eigen::Vector3d::Zero();
};

}  // namespace sarmap
