#include "engine/io/ply_mesh.hpp"

#include <cstring>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/output_columns.hpp"

namespace sarmap {
namespace {

// Appends a value's bytes; PLY's binary_little_endian is the host order on x86-64.
template <class T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

void put_color(std::string& out, const Rgb& c) {
  put(out, c.r);
  put(out, c.g);
  put(out, c.b);
}

void check(const ColoredMesh& m, const std::filesystem::path& path) {
  auto fail = [&path](const std::string& what) {
    throw Error(ErrorCode::InvalidArgument, path.string() + ": " + what);
  };
  if (m.vertex_colors.size() != m.vertices.size()) fail("one colour per vertex is needed");
  if (m.edge_colors.size() != m.edges.size()) fail("one colour per edge is needed");
  const std::size_t n = m.vertices.size();
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    if (m.faces[f].size() < 3 || m.faces[f].size() > 255) {
      fail("face " + std::to_string(f) + " has " + std::to_string(m.faces[f].size()) + " vertices (3 to 255)");
    }
    for (std::uint32_t i : m.faces[f]) {
      if (i >= n) fail("face " + std::to_string(f) + " names vertex " + std::to_string(i) + " of " + std::to_string(n));
    }
  }
  for (std::size_t e = 0; e < m.edges.size(); ++e) {
    for (std::uint32_t i : m.edges[e]) {
      if (i >= n) fail("edge " + std::to_string(e) + " names vertex " + std::to_string(i) + " of " + std::to_string(n));
    }
  }
}

}  // namespace

void write_ply_mesh(const std::filesystem::path& path, const ColoredMesh& m) {
  check(m, path);
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by sarmap\n" +
                    header_comment_lines(m.comments, "comment ", path) + "element vertex " +
                    std::to_string(m.vertices.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\n"
                    "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (!m.faces.empty()) out += "element face " + std::to_string(m.faces.size()) + "\nproperty list uchar int vertex_indices\n";
  if (!m.edges.empty()) {
    out += "element edge " + std::to_string(m.edges.size()) +
           "\nproperty int vertex1\nproperty int vertex2\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  }
  out += "end_header\n";
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    put(out, m.vertices[i].x());
    put(out, m.vertices[i].y());
    put(out, m.vertices[i].z());
    put_color(out, m.vertex_colors[i]);
  }
  for (const auto& face : m.faces) {
    put(out, static_cast<std::uint8_t>(face.size()));
    for (std::uint32_t i : face) put(out, static_cast<std::int32_t>(i));
  }
  for (std::size_t e = 0; e < m.edges.size(); ++e) {
    put(out, static_cast<std::int32_t>(m.edges[e][0]));
    put(out, static_cast<std::int32_t>(m.edges[e][1]));
    put_color(out, m.edge_colors[e]);
  }
  AtomicFileWriter writer(path);
  writer.write(out);
  writer.commit();
}

}  // namespace sarmap
