// Tests of engine/render/voxel_scene.hpp and voxel_views.hpp against exact
// geometry: one known cube seen from known cameras, which pixels it covers,
// the face and distance each ray meets, and the colours of both views.
#include "engine/render/voxel_views.hpp"

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/render/camera.hpp"
#include "engine/render/voxel_scene.hpp"

namespace sarmap::render {
namespace {

bool is_background(const RgbImage& image, int x, int y) { return image.at(x, y) == kBackground; }

// One 1 m voxel of wall centred at (0, 0, 0.5).
VoxelSet one_cube(ClassId label = ClassId::Wall) {
  VoxelSet set;
  set.voxel = 1.0f;
  set.centres = {{0, 0, 0.5f}};
  set.labels = {label};
  return set;
}

TEST(VoxelScene, OnlyFacesNotSharedWithAnotherVoxelAreBuilt) {
  EXPECT_EQ(VoxelScene(one_cube()).face_count(), 6u);
  VoxelSet two = one_cube();
  two.centres.push_back({1, 0, 0.5f});
  two.labels.push_back(ClassId::Terrain);
  EXPECT_EQ(VoxelScene(two).face_count(), 10u);
  VoxelSet bad = one_cube();
  bad.labels.clear();
  EXPECT_THROW(VoxelScene{bad}, Error);
}

TEST(VoxelScene, ARayMeetsTheFaceTurnedToIt) {
  VoxelSet two = one_cube();
  two.centres.push_back({0, 0, 1.5f});  // stacked on the first
  two.labels.push_back(ClassId::Terrain);
  const VoxelScene scene(two);
  // Along +y at z = 0.5 onto the lower cube's south face, 4.5 m away.
  auto hit = scene.trace({{0.2f, -5, 0.5f}, {0, 1, 0}});
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.voxel, 0u);
  EXPECT_NEAR(hit.t, 4.5, 1e-5);
  EXPECT_NEAR(hit.normal.y(), -1, 1e-6);
  // Straight down onto the upper cube's top.
  hit = scene.trace({{0.1f, 0.3f, 10}, {0, 0, -1}});
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.voxel, 1u);
  EXPECT_NEAR(hit.t, 8.0, 1e-5);
  EXPECT_NEAR(hit.normal.z(), 1, 1e-6);
  EXPECT_FALSE(scene.trace({{2, 0, 10}, {0, 0, -1}}).hit);
}

// Seen from straight above at 0.1 m a pixel, the 1 m cube covers exactly
// the 10 x 10 pixels whose centres lie over it; its top keeps the exact class
// colour inside, and the ring of pixels within a pixel of its border is the
// darker edge.
TEST(VoxelViews, ACubeFromAboveCoversExactlyItsPixels) {
  const VoxelSet set = one_cube(ClassId::InclinedRamp);
  const VoxelScene scene(set);
  const Camera camera = Camera::orthographic({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 0.1f, 10.0f, 40, 40);
  const HeightRange heights{0, 2};
  const VoxelViews views = render_voxel_views(scene, set, camera, heights);
  ASSERT_EQ(views.semantic.width(), 40);
  ASSERT_EQ(views.metric.height(), 40);
  int covered = 0;
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 40; ++x) {
      const bool inside = x >= 15 && x <= 24 && y >= 15 && y <= 24;
      EXPECT_EQ(!is_background(views.semantic, x, y), inside) << x << ", " << y;
      EXPECT_EQ(!is_background(views.metric, x, y), inside) << x << ", " << y;
      covered += inside ? 1 : 0;
    }
  }
  EXPECT_EQ(covered, 100);
  const Rgb ramp = class_info(ClassId::InclinedRamp).color;
  EXPECT_TRUE(views.semantic.at(20, 20) == ramp);
  EXPECT_TRUE(views.semantic.at(16, 23) == ramp);
  EXPECT_TRUE(views.metric.at(20, 20) == height_color(0.5f, heights));
  // The edge ring: the same hue, darker.
  const Rgb edge = views.semantic.at(15, 20);
  EXPECT_LT(edge.b, ramp.b);
  EXPECT_GT(edge.b, ramp.b / 2);
  EXPECT_TRUE(views.semantic.at(24, 24) == edge);
}

// A 90-degree pinhole camera 5 m south of the cube, level with its centre:
// its south face, 4.5 m away and 1 m wide, spans 100 / 9 pixels of a
// 100-pixel image; the top face is edge-on and unseen.
TEST(VoxelViews, ACubeInPerspectiveSpansItsProjectedWidth) {
  const VoxelSet set = one_cube(ClassId::Wall);
  const VoxelScene scene(set);
  const Camera camera = Camera::perspective({0, -5, 0.5f}, {0, 0, 0.5f}, {0, 0, 1}, 90.0f, 100, 100);
  const VoxelViews views = render_voxel_views(scene, set, camera, {0, 1});
  // Columns whose centres lie within 50 +- 5.56 pixels: 44 to 55.
  for (int x = 0; x < 100; ++x) {
    EXPECT_EQ(!is_background(views.semantic, x, 50), x >= 44 && x <= 55) << x;
  }
  for (int y = 0; y < 100; ++y) {
    EXPECT_EQ(!is_background(views.semantic, 50, y), y >= 44 && y <= 55) << y;
  }
  // The south face turns away from the light's height: wall red, dimmed.
  const Rgb wall = class_info(ClassId::Wall).color;
  const Rgb seen = views.semantic.at(50, 50);
  EXPECT_LT(seen.r, wall.r);
  EXPECT_GT(seen.r, seen.g);
  // project() agrees with the rays: the face's corners land on its border.
  const auto corner = camera.project({-0.5f, -0.5f, 1.0f});
  ASSERT_TRUE(corner.has_value());
  EXPECT_NEAR(corner->x(), 50 - 50.0 / 9, 1e-3);
  EXPECT_NEAR(corner->y(), 50 - 50.0 / 9, 1e-3);
  EXPECT_FALSE(camera.project({0, -6, 0.5f}).has_value());  // behind the camera
}

TEST(Camera, ObliqueAndTopViewsFrameTheWholeBox) {
  const Box3 box{{0, 0, 0}, {6, 4, 1.2f}};
  for (const Camera& camera : {oblique_camera(box, 320, 180), top_down_camera(box, 320, 180)}) {
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3f p((corner & 1) ? 6.0f : 0.0f, (corner & 2) ? 4.0f : 0.0f,
                              (corner & 4) ? 1.2f : 0.0f);
      const auto pixel = camera.project(p);
      ASSERT_TRUE(pixel.has_value());
      EXPECT_GE(pixel->x(), 0);
      EXPECT_LE(pixel->x(), 320);
      EXPECT_GE(pixel->y(), 0);
      EXPECT_LE(pixel->y(), 180);
    }
  }
  // From above, +x runs right and +y up the image.
  const Camera top = top_down_camera(box, 320, 180);
  EXPECT_LT(top.project({0, 2, 0})->x(), top.project({6, 2, 0})->x());
  EXPECT_GT(top.project({3, 0, 0})->y(), top.project({3, 4, 0})->y());
  EXPECT_THROW(Camera::perspective({0, 0, 1}, {0, 0, 0}, {0, 0, 1}, 60, 10, 10), Error);  // up along the view
}

}  // namespace
}  // namespace sarmap::render
