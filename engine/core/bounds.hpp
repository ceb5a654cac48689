// An axis-aligned box that grows to contain points; empty until the first one.
#pragma once

#include <Eigen/Core>
#include <limits>

namespace sarmap {

struct Bounds {
  Eigen::Vector3d min{Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity())};
  Eigen::Vector3d max{Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity())};

  bool empty() const { return (min.array() > max.array()).any(); }
  void extend(const Eigen::Vector3d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void extend(const Bounds& other) {
    if (other.empty()) return;
    extend(other.min);
    extend(other.max);
  }
  bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  Eigen::Vector3d size() const { return empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(max - min); }
};

}  // namespace sarmap
