// A box at any orientation (walls, platforms, obstacles, thickened wall
// segments of the topological map) and its triangles, so every module that
// turns a box into a mesh builds the same one.
#pragma once

#include <Eigen/Core>

#include "engine/geometry/classed_mesh.hpp"

namespace sarmap::geometry {

struct OrientedBox {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  // Columns are the box's local x, y, z axes in the world frame (orthonormal).
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  // Half the size along each local axis, >= 0.
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();
};

// A box of full size `size` around `center`, turned by `yaw` radians about +z:
// the shape of every wall, platform and obstacle in an arena.
OrientedBox yawed_box(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw);

// Walls and platforms stand on the floor: their bottom face is never seen and
// would only blur the floor's class in ground truth, so it can be left out.
enum class BoxFaces { All, NoBottom };

// The 8 corners (corner i takes local x's sign from bit 0, y's from bit 1,
// z's from bit 2) and 2 triangles per face, wound outwards. Label Other, no
// name. Throws sarmap::Error (InvalidArgument) for a non-finite box or a
// negative half extent.
ClassedMesh box_mesh(const OrientedBox& box, BoxFaces faces = BoxFaces::All);

// The same triangles appended to `mesh`: many boxes of one class (a map's
// walls) as one mesh, which a TriangleScene builds much faster than one mesh
// per box (figures in PERF.md, bench/geometry/segment_occlusion_bench.cpp).
void append_box(ClassedMesh& mesh, const OrientedBox& box, BoxFaces faces = BoxFaces::All);

}  // namespace sarmap::geometry
