// Running sums of points (count, sum, sum of outer products) from which the
// least-squares plane follows; adding, removing and merging are exact, so a
// segment refits after every change without keeping or revisiting old points.
#pragma once

#include <cstddef>

#include <Eigen/Core>

#include "engine/segments/plane.hpp"

namespace sarmap::segments {

class PlaneMoments {
 public:
  PlaneMoments() = default;
  // Sums as sum() and outer() gave them (a checkpoint): a rebuild by adding
  // the points again would round differently.
  PlaneMoments(std::size_t count, const Eigen::Vector3d& sum, const Eigen::Matrix3d& outer)
      : count_(count), sum_(sum), outer_(outer) {}

  void add(const Eigen::Vector3d& p);
  void remove(const Eigen::Vector3d& p);
  PlaneMoments& operator+=(const PlaneMoments& other);

  std::size_t count() const { return count_; }
  const Eigen::Vector3d& sum() const { return sum_; }
  // Sum of p p^T.
  const Eigen::Matrix3d& outer() const { return outer_; }
  Eigen::Vector3d centroid() const;
  // Population covariance of the points.
  Eigen::Matrix3d covariance() const;

 private:
  std::size_t count_ = 0;
  Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer_ = Eigen::Matrix3d::Zero();
};

struct PlaneFit {
  Plane plane;                 // through the centroid; normal sign as the eigen solver gives it
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double normal_variance = 0;  // variance of the points along the normal (smallest eigenvalue), m^2
};

// The total-least-squares plane (normal = the covariance's eigenvector of the
// smallest eigenvalue). Needs at least three points.
PlaneFit fit_plane(const PlaneMoments& moments);

}  // namespace sarmap::segments
