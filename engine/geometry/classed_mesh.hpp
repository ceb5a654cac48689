// A triangle mesh that carries the class of the surface it describes: the one
// geometric description the simulator, the topological map's wall scene and
// the ground-truth voxeliser all read, so they cannot disagree about a surface.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"

namespace sarmap::geometry {

struct ClassedMesh {
  std::vector<Eigen::Vector3f> vertices;  // world frame, metres
  std::vector<std::uint32_t> indices;     // three per triangle
  ClassId label = ClassId::Other;
  std::string name;  // "floor", "elements[i] (type)", "wall 12": names the mesh in errors

  std::size_t triangle_count() const { return indices.size() / 3; }
};

// Appends the quad a-b-c-d as the triangles a-b-c and a-c-d.
inline void add_quad(ClassedMesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
}

// Throws sarmap::Error (InvalidData, naming the mesh) when the index count is
// not a multiple of 3, an index lies outside the vertices, or a vertex is not
// finite or lies beyond kMaxSceneCoordinate.
void validate_mesh(const ClassedMesh& mesh);

}  // namespace sarmap::geometry
