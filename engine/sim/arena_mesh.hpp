// Every arena element as a triangle mesh carrying its class: the one
// geometric description that the ray caster and the ground-truth voxeliser
// both read, so they cannot disagree about where a surface is.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "engine/geometry/classed_mesh.hpp"
#include "engine/sim/arena.hpp"

namespace sarmap::sim {

using geometry::ClassedMesh;

// The element's triangles in the world frame. Elements that stand on the
// floor (walls, ramps, platforms) have no bottom face: it lies on the floor,
// is never seen, and would only blur the floor's class in ground truth.
ClassedMesh element_mesh(const ArenaElement& element);
// The floor (if any) first, then one mesh per element in order.
std::vector<ClassedMesh> arena_meshes(const Arena& arena);

// R = Rz(yaw) Ry(pitch) Rx(roll), angles in degrees.
Eigen::Matrix3d rotation_from_rpy_deg(const Eigen::Vector3d& rpy_deg);

}  // namespace sarmap::sim
