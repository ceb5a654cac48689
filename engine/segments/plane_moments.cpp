#include "engine/segments/plane_moments.hpp"

#include <algorithm>

#include <Eigen/Eigenvalues>

namespace sarmap::segments {

void PlaneMoments::add(const Eigen::Vector3d& p) {
  ++count_;
  sum_ += p;
  outer_ += p * p.transpose();
}

void PlaneMoments::remove(const Eigen::Vector3d& p) {
  if (count_ == 0) return;
  --count_;
  if (count_ == 0) {
    // Exact zero, so rounding left by many add/remove pairs cannot linger.
    *this = PlaneMoments();
    return;
  }
  sum_ -= p;
  outer_ -= p * p.transpose();
}

PlaneMoments& PlaneMoments::operator+=(const PlaneMoments& other) {
  count_ += other.count_;
  sum_ += other.sum_;
  outer_ += other.outer_;
  return *this;
}

Eigen::Vector3d PlaneMoments::centroid() const {
  return count_ == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(sum_ / static_cast<double>(count_));
}

Eigen::Matrix3d PlaneMoments::covariance() const {
  if (count_ == 0) return Eigen::Matrix3d::Zero();
  const double n = static_cast<double>(count_);
  const Eigen::Vector3d c = sum_ / n;
  return outer_ / n - c * c.transpose();
}

PlaneFit fit_plane(const PlaneMoments& moments) {
  PlaneFit fit;
  fit.centroid = moments.centroid();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(moments.covariance());
  // Eigenvalues come in increasing order.
  fit.plane.normal = solver.eigenvectors().col(0).normalized();
  fit.plane.offset = -fit.plane.normal.dot(fit.centroid);
  fit.normal_variance = std::max(0.0, solver.eigenvalues()(0));
  return fit;
}

}  // namespace sarmap::segments
