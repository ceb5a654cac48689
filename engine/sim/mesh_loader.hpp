// Loads triangles from an OBJ, STL or Collada file with assimp, node
// transforms applied and coordinates kept as written (z-up metres: Collada's
// up-axis conversion is disabled).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace sarmap::sim {

struct LoadedMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::uint32_t> indices;  // three per triangle
};

// Throws sarmap::Error(Io) when the file is missing or assimp cannot read it,
// and (InvalidData) when it holds no triangle.
LoadedMesh load_mesh_file(const std::filesystem::path& path);

}  // namespace sarmap::sim
