#include "engine/core/pose.hpp"

#include <cmath>
#include <sstream>

#include "engine/core/error.hpp"
#include "engine/core/point_buffer.hpp"

namespace sarmap {
namespace {

constexpr double kOrthonormalTolerance = 1e-3;

void validate_rotation(const Eigen::Matrix3d& r, const Eigen::Vector3d& t, std::string_view what) {
  if (!r.allFinite() || !t.allFinite()) {
    throw Error(ErrorCode::InvalidData, std::string(what) + ": pose contains NaN or infinite values");
  }
  const double deviation = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (deviation > kOrthonormalTolerance) {
    std::ostringstream msg;
    msg << what << ": rotation is not orthonormal (|R^T R - I| = " << deviation
        << ", tolerance " << kOrthonormalTolerance << ")";
    throw Error(ErrorCode::InvalidData, msg.str());
  }
  if (r.determinant() < 0) {
    throw Error(ErrorCode::InvalidData,
                std::string(what) + ": rotation is a reflection (determinant -1), not a rotation");
  }
}

}  // namespace

Pose::Pose(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation, std::string_view what)
    : rotation_(rotation), translation_(translation) {
  validate_rotation(rotation_, translation_, what);
}

Pose Pose::from_matrix(const Eigen::Matrix4d& m, std::string_view what) {
  const Eigen::RowVector4d last = m.row(3);
  if (!m.allFinite()) {
    throw Error(ErrorCode::InvalidData, std::string(what) + ": pose contains NaN or infinite values");
  }
  if ((last - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6) {
    std::ostringstream msg;
    msg << what << ": last row of the 4x4 pose must be [0 0 0 1], got [" << last << "]";
    throw Error(ErrorCode::InvalidData, msg.str());
  }
  return Pose(m.topLeftCorner<3, 3>(), m.topRightCorner<3, 1>(), what);
}

Pose Pose::from_row_major(std::span<const double> v, std::string_view what) {
  if (v.size() != 16) {
    throw Error(ErrorCode::InvalidData, std::string(what) + ": a pose needs 16 numbers (row-major 4x4), got " +
                                            std::to_string(v.size()));
  }
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = v[static_cast<std::size_t>(r * 4 + c)];
  }
  return from_matrix(m, what);
}

Pose Pose::from_quaternion(double qx, double qy, double qz, double qw, const Eigen::Vector3d& t,
                           std::string_view what) {
  Eigen::Quaterniond q(qw, qx, qy, qz);
  const double norm = q.norm();
  if (!std::isfinite(norm) || norm < 1e-9) {
    throw Error(ErrorCode::InvalidData, std::string(what) + ": quaternion is zero or not finite");
  }
  q.coeffs() /= norm;
  return Pose(q.toRotationMatrix(), t, what);
}

Eigen::Matrix4d Pose::matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rotation_;
  m.topRightCorner<3, 1>() = translation_;
  return m;
}

Pose Pose::operator*(const Pose& other) const {
  Pose out;
  out.rotation_ = rotation_ * other.rotation_;
  out.translation_ = rotation_ * other.translation_ + translation_;
  return out;
}

Pose Pose::inverse() const {
  Pose out;
  out.rotation_ = rotation_.transpose();
  out.translation_ = -(out.rotation_ * translation_);
  return out;
}

void Pose::apply(PointBuffer& points) const {
  const Eigen::Matrix3f r = rotation_.cast<float>();
  const Eigen::Vector3f t = translation_.cast<float>();
  auto xs = points.x();
  auto ys = points.y();
  auto zs = points.z();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f p(xs[i], ys[i], zs[i]);
    const Eigen::Vector3f q = r * p + t;
    xs[i] = q.x();
    ys[i] = q.y();
    zs[i] = q.z();
  }
  if (points.has_normals()) {
    auto nx = points.normal_x();
    auto ny = points.normal_y();
    auto nz = points.normal_z();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3f n = r * Eigen::Vector3f(nx[i], ny[i], nz[i]);
      nx[i] = n.x();
      ny[i] = n.y();
      nz[i] = n.z();
    }
  }
}

}  // namespace sarmap
