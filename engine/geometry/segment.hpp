// A straight line segment between two points, in double precision: a
// candidate edge of the topological map between two robot stand points, the
// unit of the scene's batched occlusion query and of its exact reference.
#pragma once

#include <Eigen/Core>

namespace sarmap::geometry {

struct Segment {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
};

}  // namespace sarmap::geometry
