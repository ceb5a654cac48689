#include "engine/io/ply_mesh.hpp"

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/io/ply.hpp"
#include "tests/io/scratch_folder.hpp"

namespace sarmap {
namespace {

ColoredMesh quad_and_edge() {
  ColoredMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.5f}};
  m.vertex_colors.assign(4, Rgb{10, 20, 30});
  m.faces = {{0, 1, 2, 3}};
  m.edges = {{0, 2}};
  m.edge_colors = {Rgb{1, 2, 3}};
  return m;
}

TEST(PlyMesh, WritesVerticesFacesAndEdgesThatThePointReaderOpens) {
  test::ScratchFolder dir;
  write_ply_mesh(dir / "m.ply", quad_and_edge());
  std::ifstream in(dir / "m.ply", std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  const std::string text = bytes.str();
  EXPECT_NE(text.find("element vertex 4\n"), std::string::npos);
  EXPECT_NE(text.find("element face 1\nproperty list uchar int vertex_indices\n"), std::string::npos);
  EXPECT_NE(text.find("element edge 1\nproperty int vertex1\nproperty int vertex2\n"), std::string::npos);
  const std::size_t body = text.find("end_header\n") + 11;
  // 4 vertices of 15 bytes, one face of 1 + 4 x 4, one edge of 8 + 3.
  EXPECT_EQ(text.size() - body, 4u * 15 + 17 + 11);
  const PointBuffer points = read_ply(dir / "m.ply");
  ASSERT_EQ(points.size(), 4u);
  EXPECT_FLOAT_EQ(points.z()[3], 0.5f);
  EXPECT_EQ(points.red()[2], 10);
}

TEST(PlyMesh, WritesHeaderCommentsThePointReaderReturns) {
  test::ScratchFolder dir;
  ColoredMesh m = quad_and_edge();
  m.comments = {"voxel_size 0.1"};
  write_ply_mesh(dir / "m.ply", m);
  PointCloudFileInfo info;
  EXPECT_EQ(read_ply(dir / "m.ply", &info).size(), 4u);
  EXPECT_EQ(info.comments, (std::vector<std::string>{"written by sarmap", "voxel_size 0.1"}));
  m.comments = {"two\nlines"};
  EXPECT_THROW(write_ply_mesh(dir / "n.ply", m), Error);
}

TEST(PlyMesh, RefusesInconsistentMeshes) {
  test::ScratchFolder dir;
  ColoredMesh m = quad_and_edge();
  m.faces[0][2] = 9;
  EXPECT_THROW(write_ply_mesh(dir / "a.ply", m), Error);
  m = quad_and_edge();
  m.faces[0] = {0, 1};
  EXPECT_THROW(write_ply_mesh(dir / "b.ply", m), Error);
  m = quad_and_edge();
  m.edge_colors.clear();
  EXPECT_THROW(write_ply_mesh(dir / "c.ply", m), Error);
  m = quad_and_edge();
  m.edges[0][1] = 4;
  EXPECT_THROW(write_ply_mesh(dir / "d.ply", m), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "a.ply"));
}

}  // namespace
}  // namespace sarmap
