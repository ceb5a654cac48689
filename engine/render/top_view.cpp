#include "engine/render/top_view.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "engine/render/raster.hpp"
#include "engine/render/voxel_views.hpp"

namespace sarmap::render {
namespace {

// How much of the white background the map's colours are mixed with.
constexpr float kWashOut = 0.45f;

Rgb washed(Rgb c) {
  const auto mix = [](std::uint8_t v) {
    return static_cast<std::uint8_t>(
        std::lround(static_cast<float>(v) + kWashOut * (255.0f - static_cast<float>(v))));
  };
  return {mix(c.r), mix(c.g), mix(c.b)};
}

Rgb darker(Rgb c) {
  return {static_cast<std::uint8_t>(c.r * 3 / 5), static_cast<std::uint8_t>(c.g * 3 / 5),
          static_cast<std::uint8_t>(c.b * 3 / 5)};
}

// graph.ply's colours: a node in the class of the ground it stands on.
Rgb node_color(topo::NodeKind kind) {
  switch (kind) {
    case topo::NodeKind::Terrain:
      return class_info(ClassId::Terrain).color;
    case topo::NodeKind::FlatRamp:
      return class_info(ClassId::FlatRamp).color;
    case topo::NodeKind::RampFoot:
    case topo::NodeKind::RampTop:
      break;
  }
  return class_info(ClassId::InclinedRamp).color;
}

std::optional<Eigen::Vector2f> pixel_of(const Camera& camera, const Eigen::Vector3d& p) {
  return camera.project(p.cast<float>());
}

bool alive(const std::vector<topo::TopoNode>& nodes, std::uint32_t id) {
  return id < nodes.size() && nodes[id].alive;
}

}  // namespace

void draw_overlays(RgbImage& image, const Camera& camera, const MapOverlays& overlays) {
  // Sizes in pixels for a 720-pixel-high picture, scaled with the image.
  const float unit = std::max(1.0f, static_cast<float>(std::min(image.width(), image.height())) / 720.0f);
  for (const segments::Segment& s : overlays.segments) {
    std::array<Eigen::Vector2f, 4> corners;
    bool visible = true;
    const auto world = s.rectangle.corners();
    for (std::size_t i = 0; i < 4; ++i) {
      const auto p = pixel_of(camera, world[i]);
      if (!p)
        visible = false;
      else
        corners[i] = *p;
    }
    if (visible) draw_polygon(image, corners, 2.0f * unit, darker(class_info(s.label).color));
  }
  // Roadmap edges first, so the spanning tree's edges lie on top of them.
  for (const bool tree : {false, true}) {
    for (const topo::TopoEdge& e : overlays.edges) {
      if (e.in_tree != tree || !alive(overlays.nodes, e.a) || !alive(overlays.nodes, e.b)) continue;
      const auto a = pixel_of(camera, overlays.nodes[e.a].position);
      const auto b = pixel_of(camera, overlays.nodes[e.b].position);
      if (a && b)
        draw_line(image, *a, *b, (tree ? 2.5f : 1.5f) * unit, tree ? kTreeEdgeColor : kRoadmapEdgeColor);
    }
  }
  for (std::size_t i = 1; i < overlays.path.size(); ++i) {
    const auto a = pixel_of(camera, overlays.path[i - 1]);
    const auto b = pixel_of(camera, overlays.path[i]);
    if (a && b) draw_line(image, *a, *b, 5.0f * unit, kPathColor);
  }
  for (const topo::TopoNode& n : overlays.nodes) {
    if (!n.alive) continue;
    const auto p = pixel_of(camera, n.position);
    if (!p) continue;
    fill_disc(image, *p, 6.0f * unit, kTreeEdgeColor);
    fill_disc(image, *p, 4.5f * unit, node_color(n.kind));
  }
  if (!overlays.path.empty()) {
    for (const Eigen::Vector3d& end : {overlays.path.front(), overlays.path.back()}) {
      if (const auto p = pixel_of(camera, end)) {
        fill_disc(image, *p, 8.0f * unit, kTreeEdgeColor);
        fill_disc(image, *p, 6.0f * unit, kPathColor);
      }
    }
  }
}

RgbImage render_top_view(const VoxelScene& scene, const VoxelSet& voxels, const Camera& camera,
                         const MapOverlays& overlays) {
  RgbImage image(camera.width(), camera.height(), kBackground);
  tbb::parallel_for(tbb::blocked_range<int>(0, camera.height()), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < camera.width(); ++x) {
        const VoxelScene::Hit hit =
            scene.trace(camera.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f));
        if (hit.hit) image.set(x, y, washed(class_info(voxels.labels[hit.voxel]).color));
      }
    }
  });
  draw_overlays(image, camera, overlays);
  return image;
}

}  // namespace sarmap::render
