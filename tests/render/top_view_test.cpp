// Tests of engine/render/top_view.hpp: segments, graph nodes and edges and a
// path drawn at the pixels the top-down camera projects them to.
#include "engine/render/top_view.hpp"

#include <gtest/gtest.h>

#include "engine/render/camera.hpp"
#include "engine/render/voxel_views.hpp"

namespace sarmap::render {
namespace {

// A 4 x 2 m box framed in 400 x 200 pixels: 0.0104 m a pixel, the box's
// centre (2, 1) at the image's centre (200, 100).
const Box3 kBox{{0, 0, 0}, {4, 2, 1}};
constexpr float kMetresPerPixel = 1.04f * 4.0f / 400.0f;

Eigen::Vector2f expected_pixel(double x, double y) {
  return {200.0f + static_cast<float>(x - 2) / kMetresPerPixel,
          100.0f - static_cast<float>(y - 1) / kMetresPerPixel};
}

topo::TopoNode node(std::uint32_t id, double x, double y, topo::NodeKind kind) {
  topo::TopoNode n;
  n.id = id;
  n.position = {x, y, 0};
  n.kind = kind;
  return n;
}

TEST(TopView, OverlaysLandWhereTheCameraProjectsThem) {
  const Camera camera = top_down_camera(kBox, 400, 200);
  const auto centre = camera.project({2, 1, 0});
  ASSERT_TRUE(centre.has_value());
  EXPECT_NEAR(centre->x(), 200, 1e-3);
  EXPECT_NEAR(centre->y(), 100, 1e-3);

  MapOverlays overlays;
  segments::Segment wall;
  wall.label = ClassId::Wall;
  wall.rectangle.center = {2, 1, 0.5};
  wall.rectangle.axes = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
  wall.rectangle.half_extents = {1.5, 0.5};  // x 0.5 to 3.5, y 0.5 to 1.5
  overlays.segments.push_back(wall);
  overlays.nodes = {node(0, 1, 1, topo::NodeKind::Terrain), node(1, 3, 1, topo::NodeKind::FlatRamp)};
  overlays.edges.push_back({0, 1, 2.0, 0.0, ClassId::Terrain, true});
  overlays.path = {{1, 0.2, 0}, {3, 0.2, 0}};

  RgbImage image(400, 200, kBackground);
  draw_overlays(image, camera, overlays);
  const auto at = [&image](const Eigen::Vector2f& p) {
    return image.at(static_cast<int>(p.x()), static_cast<int>(p.y()));
  };
  // Nodes: filled in the class of their ground, ringed in black.
  EXPECT_TRUE(at(expected_pixel(1, 1)) == class_info(ClassId::Terrain).color);
  EXPECT_TRUE(at(expected_pixel(3, 1)) == class_info(ClassId::FlatRamp).color);
  EXPECT_TRUE(at(expected_pixel(1, 1) + Eigen::Vector2f(5.5f, 0)) == kTreeEdgeColor);
  // The tree edge between them, black, halfway.
  EXPECT_TRUE(at(expected_pixel(2, 1)) == kTreeEdgeColor);
  // The segment's outline on its left side (x = 0.5), darker wall red; inside it, nothing.
  const Rgb outline = at(expected_pixel(0.5, 0.9));
  EXPECT_GT(outline.r, 100);
  EXPECT_LT(outline.g, 40);
  EXPECT_TRUE(at(expected_pixel(1.5, 1.3)) == kBackground);
  // The path along y = 0.2, with its ends marked.
  EXPECT_TRUE(at(expected_pixel(2, 0.2)) == kPathColor);
  EXPECT_TRUE(at(expected_pixel(1, 0.2)) == kPathColor);
  EXPECT_TRUE(at(expected_pixel(2, 0.35)) == kBackground);
}

TEST(TopView, RetiredNodesAndTheirEdgesAreLeftOut) {
  const Camera camera = top_down_camera(kBox, 400, 200);
  MapOverlays overlays;
  overlays.nodes = {node(0, 1, 1, topo::NodeKind::Terrain), node(1, 3, 1, topo::NodeKind::Terrain)};
  overlays.nodes[1].alive = false;
  overlays.edges.push_back({0, 1, 2.0, 0.0, ClassId::Terrain, true});
  overlays.edges.push_back({0, 7, 2.0, 0.0, ClassId::Terrain, true});  // a node the list lacks
  RgbImage image(400, 200, kBackground);
  draw_overlays(image, camera, overlays);
  const Eigen::Vector2f p = expected_pixel(2, 1);
  EXPECT_TRUE(image.at(static_cast<int>(p.x()), static_cast<int>(p.y())) == kBackground);
  const Eigen::Vector2f q = expected_pixel(3, 1);
  EXPECT_TRUE(image.at(static_cast<int>(q.x()), static_cast<int>(q.y())) == kBackground);
}

// The map under the overlays: a voxel of terrain seen from above, in its class
// colour washed towards white.
TEST(TopView, TheMapShowsUnderTheOverlays) {
  VoxelSet voxels;
  voxels.voxel = 0.5f;
  voxels.centres = {{0.75f, 0.75f, 0.25f}};
  voxels.labels = {ClassId::Terrain};
  const VoxelScene scene(voxels);
  const Camera camera = top_down_camera(kBox, 400, 200);
  const RgbImage image = render_top_view(scene, voxels, camera, {});
  const Eigen::Vector2f p = expected_pixel(0.75, 0.75);
  const Rgb c = image.at(static_cast<int>(p.x()), static_cast<int>(p.y()));
  const Rgb terrain = class_info(ClassId::Terrain).color;
  EXPECT_FALSE(c == kBackground);
  EXPECT_GT(c.b, terrain.b);  // washed out
  EXPECT_GT(c.r, c.b);        // still yellow
  const Eigen::Vector2f q = expected_pixel(2, 1);
  EXPECT_TRUE(image.at(static_cast<int>(q.x()), static_cast<int>(q.y())) == kBackground);
}

}  // namespace
}  // namespace sarmap::render
