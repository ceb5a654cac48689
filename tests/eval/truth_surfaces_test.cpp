// The arena's true faces: kinds, planes and outlines of the default arena's
// faces, faces cut in two by a wall standing against them, and the fraction
// of a face that observed voxels cover.
#include "engine/eval/truth_surfaces.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/core/degrees.hpp"
#include "engine/eval/face_pieces.hpp"

namespace sarmap::eval {
namespace {

sim::Arena shipped_default_arena() { return sim::load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json"); }

sim::Arena small_arena_with(const std::string& elements) {
  return sim::parse_arena(R"({"name": "t", "bounds": {"min": [0, 0, 0], "max": [4, 4, 2]}, "floor": true,
    "elements": [)" + elements + R"(],
    "trajectory": {"waypoints": [[0.5, 2], [3.5, 2]], "height": 0.5, "frames": 2, "pitch_deg": 0},
    "sensor": {"type": "depth_camera", "width": 8, "height": 6, "fx": 7, "fy": 7, "cx": 4, "cy": 3,
               "min_range": 0.1, "max_range": 6, "noise": "none"}})",
                          "t.json", ".");
}

std::vector<const TruthFace*> of_kind(const std::vector<TruthFace>& faces, FaceKind kind) {
  std::vector<const TruthFace*> out;
  for (const TruthFace& f : faces) {
    if (f.kind == kind) out.push_back(&f);
  }
  return out;
}

const TruthFace* facing(const std::vector<TruthFace>& faces, std::size_t element, const Eigen::Vector3d& normal,
                        std::size_t piece = 0) {
  for (const TruthFace& f : faces) {
    if (f.element == element && (f.normal - normal).norm() < 1e-6 && f.piece == piece) return &f;
  }
  return nullptr;
}

TEST(TruthSurfaces, DefaultArenaFaces) {
  const std::vector<TruthFace> faces = truth_faces(shipped_default_arena());
  ASSERT_EQ(of_kind(faces, FaceKind::Floor).size(), 1u);
  EXPECT_EQ(of_kind(faces, FaceKind::WallFace).size(), 8u);
  EXPECT_EQ(of_kind(faces, FaceKind::RampDeck).size(), 2u);
  EXPECT_EQ(of_kind(faces, FaceKind::PlatformTop).size(), 1u);
  // Wall ends and tops (4 x 3), ramp sides and backs (2 x 3), platform sides (4).
  EXPECT_EQ(of_kind(faces, FaceKind::Side).size(), 22u);

  const TruthFace& floor = *of_kind(faces, FaceKind::Floor).front();
  EXPECT_EQ(floor.label, ClassId::Terrain);
  EXPECT_FALSE(floor.element.has_value());
  EXPECT_NEAR(floor.area_m2, 24.0, 1e-6);
  EXPECT_NEAR(floor.normal.z(), 1.0, 1e-9);

  // Wall 0 runs along y = 0; its inner face is open between the walls at its ends.
  const TruthFace* inner = facing(faces, 0, Eigen::Vector3d::UnitY());
  ASSERT_NE(inner, nullptr);
  EXPECT_EQ(inner->kind, FaceKind::WallFace);
  EXPECT_EQ(inner->label, ClassId::Wall);
  EXPECT_NEAR(inner->distance({3, 0.05, 0.6}), 0.0, 1e-6);
  EXPECT_NEAR(inner->area_m2, 5.9 * 1.2, 0.03);
  EXPECT_TRUE(inner->contains({3, 0.05, 0.6}, 0));
  EXPECT_TRUE(inner->contains({5.9, 0.05, 1.1}, 0));
  EXPECT_FALSE(inner->contains({6.0, 0.05, 0.6}, 0));  // inside wall 1
  EXPECT_TRUE(inner->contains({6.0, 0.05, 0.6}, 0.1));
  EXPECT_FALSE(inner->contains({3, 0.05, 1.3}, 0));
  EXPECT_EQ(inner->pieces, 1u);

  // Ramp 4 rises 15 degrees towards +x from its low edge at x = 0.9.
  const TruthFace* deck = of_kind(faces, FaceKind::RampDeck).front();
  EXPECT_EQ(deck->element, 4u);
  EXPECT_EQ(deck->label, ClassId::InclinedRamp);
  EXPECT_NEAR(deck->slope_deg, 15.0, 1e-4);
  EXPECT_NEAR((deck->normal - Eigen::Vector3d(-std::sin(15 * kDeg), 0, std::cos(15 * kDeg))).norm(), 0, 1e-6);
  EXPECT_NEAR(deck->distance({0.9, 0.8, 0}), 0.0, 1e-6);
  EXPECT_NEAR(deck->area_m2, 1.2 / std::cos(15 * kDeg) * 1.0, 1e-5);
  // Ramp 5 is turned 180 degrees: it rises towards -x at 20 degrees.
  EXPECT_NEAR(of_kind(faces, FaceKind::RampDeck)[1]->normal.x(), std::sin(20 * kDeg), 1e-6);

  const TruthFace* top = of_kind(faces, FaceKind::PlatformTop).front();
  EXPECT_EQ(top->label, ClassId::FlatRamp);
  EXPECT_NEAR(top->distance({4.5, 0.8, 0.3}), 0.0, 1e-6);
  EXPECT_NEAR(top->area_m2, 1.2, 1e-6);
  EXPECT_NEAR((top->center - Eigen::Vector3d(4.5, 0.8, 0.3)).norm(), 0, 1e-6);
}

TEST(TruthSurfaces, AWallStandingAgainstAFaceCutsItInTwo) {
  const std::vector<TruthFace> faces = truth_faces(small_arena_with(R"(
    {"type": "wall", "from": [0.5, 1], "to": [3.5, 1], "height": 1, "thickness": 0.1},
    {"type": "wall", "from": [2, 1], "to": [2, 3], "height": 1, "thickness": 0.1})"));
  // Wall 1 stands on the +y side of wall 0, from x = 1.95 to 2.05.
  const TruthFace* west = facing(faces, 0, Eigen::Vector3d::UnitY(), 0);
  const TruthFace* east = facing(faces, 0, Eigen::Vector3d::UnitY(), 1);
  ASSERT_NE(west, nullptr);
  ASSERT_NE(east, nullptr);
  if (west->center.x() > east->center.x()) std::swap(west, east);
  EXPECT_EQ(west->pieces, 2u);
  EXPECT_NEAR(west->area_m2, 1.5, 0.03);  // x 0.45 to 1.95
  EXPECT_NEAR(east->area_m2, 1.5, 0.03);  // x 2.05 to 3.55
  EXPECT_TRUE(west->contains({1.9, 1.05, 0.5}, 0));
  EXPECT_FALSE(west->contains({2.0, 1.05, 0.5}, 0));
  EXPECT_FALSE(east->contains({2.0, 1.05, 0.5}, 0));
  EXPECT_TRUE(east->contains({2.1, 1.05, 0.5}, 0));
  // The far side is whole; wall 1's faces lose the strip inside wall 0.
  const TruthFace* south = facing(faces, 0, -Eigen::Vector3d::UnitY());
  ASSERT_NE(south, nullptr);
  EXPECT_EQ(south->pieces, 1u);
  EXPECT_NEAR(south->area_m2, 3.1, 1e-6);
  const TruthFace* side = facing(faces, 1, -Eigen::Vector3d::UnitX());
  ASSERT_NE(side, nullptr);
  EXPECT_EQ(side->pieces, 1u);
  EXPECT_NEAR(side->area_m2, 2.0, 0.03);  // y 1.05 to 3.05
  EXPECT_FALSE(side->contains({1.95, 1.0, 0.5}, 0));
}

TEST(TruthSurfaces, BoxesHideButGiveNoFaces) {
  const std::vector<TruthFace> faces = truth_faces(small_arena_with(R"(
    {"type": "wall", "from": [0.5, 1], "to": [3.5, 1], "height": 1, "thickness": 0.1},
    {"type": "box", "center": [2, 1.3, 0.25], "size": [0.4, 0.5, 0.5]})"));
  for (const TruthFace& f : faces) EXPECT_NE(f.element, 1u) << f.name;
  // The box covers the face's lower middle: one U-shaped piece, less its area.
  const TruthFace* face = facing(faces, 0, Eigen::Vector3d::UnitY());
  ASSERT_NE(face, nullptr);
  EXPECT_EQ(face->pieces, 1u);
  EXPECT_NEAR(face->area_m2, 3.1 - 0.4 * 0.5, 0.03);
}

TEST(TruthSurfaces, SeenFractionCountsObservedVoxelsOnEitherSide) {
  const std::vector<TruthFace> faces = truth_faces(shipped_default_arena());
  const TruthFace& top = *of_kind(faces, FaceKind::PlatformTop).front();  // x 3.9..5.1, y 0.3..1.3, z 0.3
  sim::GroundTruthGrid grid;
  grid.resolution = 0.1;
  EXPECT_EQ(seen_fraction(top, grid), 0.0);
  // The top lies on the voxel boundary z = 0.3: mark the voxels above it
  // where x < 4.5 and those below it elsewhere.
  for (int x = 39; x < 51; ++x) {
    for (int y = 3; y < 13; ++y) {
      const int z = x < 45 ? 3 : 2;
      grid.occupied[{x, y, z}].observed = true;
    }
  }
  EXPECT_NEAR(seen_fraction(top, grid), 1.0, 1e-9);
  // Unobserved voxels do not count.
  for (int y = 3; y < 13; ++y) {
    for (int x = 39; x < 45; ++x) grid.occupied[{x, y, 3}].observed = false;
  }
  EXPECT_NEAR(seen_fraction(top, grid), 0.5, 1e-9);
}

TEST(TruthSurfaces, ConvexSolidOfARamp) {
  const sim::Arena arena = shipped_default_arena();
  const auto solid = element_solid(arena.elements[4], sim::element_mesh(arena.elements[4]));
  ASSERT_TRUE(solid.has_value());
  // Under the deck (1.5, 0.8: deck at 0.6 * tan 15 = 0.16 m) and above it.
  EXPECT_TRUE(solid->contains({1.5, 0.8, 0.1}));
  EXPECT_FALSE(solid->contains({1.5, 0.8, 0.2}));
  EXPECT_FALSE(solid->contains({1.5, 0.8, -0.01}));
  EXPECT_FALSE(solid->contains({1.5, 1.31, 0.05}));
  sim::ArenaElement mesh_element;
  mesh_element.shape = sim::MeshSpec{};
  EXPECT_FALSE(element_solid(mesh_element, sim::element_mesh(arena.elements[4])).has_value());
}

}  // namespace
}  // namespace sarmap::eval
