// Tests of engine/sim/arena_mesh.hpp and mesh_loader.hpp: element shapes,
// mesh files with their node transforms, and the Collada up-axis rule.
#include "engine/sim/arena_mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/core/error.hpp"
#include "engine/geometry/triangle_scene.hpp"
#include "engine/sim/mesh_loader.hpp"
#include "tests/sim/test_arenas.hpp"

namespace sarmap::sim {
namespace {

using nlohmann::json;

double mesh_area(const ClassedMesh& m) {
  double a = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const Eigen::Vector3d p0 = m.vertices[m.indices[t]].cast<double>();
    const Eigen::Vector3d p1 = m.vertices[m.indices[t + 1]].cast<double>();
    const Eigen::Vector3d p2 = m.vertices[m.indices[t + 2]].cast<double>();
    a += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  return a;
}

Eigen::AlignedBox3f mesh_box(const ClassedMesh& m) {
  Eigen::AlignedBox3f b;
  for (const auto& v : m.vertices) b.extend(v);
  return b;
}

TEST(ArenaMesh, WallIsABoxExtendedBeyondItsEnds) {
  ArenaElement e;
  e.shape = WallSpec{{1, 2}, {4, 2}, 1.2, 0.1};
  e.label = ClassId::Wall;
  const ClassedMesh m = element_mesh(e);
  const auto b = mesh_box(m);
  EXPECT_NEAR(b.min().x(), 0.95, 1e-6);
  EXPECT_NEAR(b.max().x(), 4.05, 1e-6);
  EXPECT_NEAR(b.min().y(), 1.95, 1e-6);
  EXPECT_NEAR(b.max().y(), 2.05, 1e-6);
  EXPECT_NEAR(b.min().z(), 0.0, 1e-6);
  EXPECT_NEAR(b.max().z(), 1.2, 1e-6);
  // Top and four sides, no bottom.
  EXPECT_EQ(m.triangle_count(), 10u);
  EXPECT_NEAR(mesh_area(m), 3.1 * 0.1 + 2 * 3.1 * 1.2 + 2 * 0.1 * 1.2, 1e-5);
  EXPECT_EQ(m.label, ClassId::Wall);
}

TEST(ArenaMesh, InclinedRampIsAWedgeRisingToLocalX) {
  ArenaElement e;
  e.shape = InclinedRampSpec{{2, 1}, 1.2, 1.0, 15, 90};
  e.label = ClassId::InclinedRamp;
  const ClassedMesh m = element_mesh(e);
  const double top = 1.2 * std::tan(15 * std::numbers::pi / 180);
  const auto b = mesh_box(m);
  // Yaw 90: the run lies along y, the width along x.
  EXPECT_NEAR(b.min().x(), 1.5, 1e-6);
  EXPECT_NEAR(b.max().x(), 2.5, 1e-6);
  EXPECT_NEAR(b.min().y(), 0.4, 1e-6);
  EXPECT_NEAR(b.max().y(), 1.6, 1e-6);
  EXPECT_NEAR(b.max().z(), top, 1e-6);
  const double slope = std::hypot(1.2, top) * 1.0;
  EXPECT_NEAR(mesh_area(m), slope + top * 1.0 + 2 * 0.5 * 1.2 * top, 1e-5);
}

TEST(ArenaMesh, RpyRotationOrder) {
  // Rz(90) after Rx(90): x stays x under Rx, then turns to y.
  const Eigen::Matrix3d r = rotation_from_rpy_deg({90, 0, 90});
  EXPECT_TRUE((r * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  // y goes to z under Rx(90), and z is kept by Rz.
  EXPECT_TRUE((r * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
}

TEST(ArenaMesh, MeshElementAppliesNodeTransformAndPlacement) {
  json j = testing::base_arena_json();
  j["elements"] = json::parse(R"([{"type": "mesh", "path": "meshes/full_ramp.dae", "position": [1, 3, 0],
                                   "rpy_deg": [0, 0, 90], "scale": [1, 1, 1], "label": "inclined_ramp"}])");
  const Arena a = testing::parse_test_arena(j, SARMAP_SOURCE_DIR "/datasets/arenas");
  const std::vector<ClassedMesh> meshes = arena_meshes(a);
  ASSERT_EQ(meshes.size(), 2u);  // floor + mesh
  const ClassedMesh& m = meshes[1];
  EXPECT_EQ(m.label, ClassId::InclinedRamp);
  EXPECT_EQ(m.triangle_count(), 6u);
  // File footprint x 0..1.2 (node matrix), y -0.6..0.6; turned by 90 degrees
  // and moved to (1, 3): x 0.4..1.6, y 3..4.2, rising towards +y.
  const auto b = mesh_box(m);
  EXPECT_NEAR(b.min().x(), 0.4, 1e-5);
  EXPECT_NEAR(b.max().x(), 1.6, 1e-5);
  EXPECT_NEAR(b.min().y(), 3.0, 1e-5);
  EXPECT_NEAR(b.max().y(), 4.2, 1e-5);
  const geometry::TriangleScene scene(meshes);
  const auto hit = scene.intersect({1.0f, 3.6f, 2.0f}, {0, 0, -1}, 0, 10);
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.label, ClassId::InclinedRamp);
  EXPECT_NEAR(hit.t, 2.0 - 0.6 * std::tan(15 * std::numbers::pi / 180), 1e-5);
}

TEST(ArenaMesh, MeshScaleAndObj) {
  json j = testing::base_arena_json();
  j["elements"] = json::parse(R"([{"type": "mesh", "path": "data/unit_square.obj", "position": [1, 1, 0],
                                   "scale": [2, 1, 2]}])");
  const Arena a = testing::parse_test_arena(j, SARMAP_SOURCE_DIR "/tests/sim");
  const ClassedMesh m = arena_meshes(a)[1];
  EXPECT_EQ(m.label, ClassId::Other);
  const auto b = mesh_box(m);
  EXPECT_NEAR(b.min().x(), 1.0, 1e-6);
  EXPECT_NEAR(b.max().x(), 3.0, 1e-6);
  EXPECT_NEAR(b.max().y(), 2.0, 1e-6);
  EXPECT_NEAR(b.max().z(), 1.0, 1e-6);
  EXPECT_NEAR(mesh_area(m), 2.0, 1e-6);
}

TEST(MeshLoader, KeepsCoordinatesOfAYUpColladaFile) {
  const LoadedMesh m = load_mesh_file(SARMAP_SOURCE_DIR "/tests/sim/data/y_up_triangle.dae");
  ASSERT_EQ(m.vertices.size(), 3u);
  ASSERT_EQ(m.indices.size(), 3u);
  EXPECT_TRUE(m.vertices[m.indices[2]].isApprox(Eigen::Vector3f(0, 0, 1)))
      << m.vertices[m.indices[2]].transpose();
}

TEST(MeshLoader, BrokenMeshIsAnErrorNamingTheElement) {
  json j = testing::base_arena_json();
  j["elements"] = json::parse(R"([{"type": "mesh", "path": "data/not_a_mesh.obj"}])");
  try {
    testing::parse_test_arena(j, SARMAP_SOURCE_DIR "/tests/sim");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("elements[0] (mesh): path:"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sarmap::sim
