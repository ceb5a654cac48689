// Coloured polygons and line segments as a binary PLY file (vertex, face and
// edge elements), the form MeshLab, CloudCompare and Open3D open: segment
// rectangles as quads, graph nodes and edges as points and lines.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"

namespace sarmap {

struct ColoredMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Rgb> vertex_colors;                  // one per vertex
  std::vector<std::vector<std::uint32_t>> faces;   // vertex indices, 3 or more each
  std::vector<std::array<std::uint32_t, 2>> edges;
  std::vector<Rgb> edge_colors;                    // one per edge
  std::vector<std::string> comments;               // header comment lines, e.g. "voxel_size 0.05"
};

// Writes atomically. Throws sarmap::Error (InvalidArgument) for a colour
// count that does not match, an index out of range or a face of fewer than
// three or more than 255 vertices, or a comment with a line break; (Io) when
// the file cannot be written.
void write_ply_mesh(const std::filesystem::path& path, const ColoredMesh& mesh);

}  // namespace sarmap
