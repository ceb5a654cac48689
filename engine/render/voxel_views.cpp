#include "engine/render/voxel_views.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace sarmap::render {
namespace {

// From above and to the south-west, so the top and the two side faces an
// oblique view sees each get a different brightness. Shading is scaled so a
// face looking straight up keeps its exact colour: floors and platform tops,
// most of a map, show the class colours of the legend.
const Eigen::Vector3f kLight = Eigen::Vector3f(-0.3f, -0.6f, 1.0f).normalized();
constexpr float kAmbient = 0.35f;

float face_shade(const Eigen::Vector3f& normal) {
  return kAmbient + (1.0f - kAmbient) * std::max(0.0f, normal.dot(kLight)) / kLight.z();
}
constexpr float kEdgeShade = 0.72f;
// Edges are drawn only where a voxel spans at least this many pixels;
// below it they would turn the whole picture dark.
constexpr float kMinPixelsForEdges = 4.0f;

Rgb scaled(Rgb c, float s) {
  const auto channel = [s](std::uint8_t v) {
    return static_cast<std::uint8_t>(std::clamp(std::lround(static_cast<float>(v) * s), 0L, 255L));
  };
  return {channel(c.r), channel(c.g), channel(c.b)};
}

// Whether the hit point lies within one pixel of its face's border.
bool on_voxel_edge(const Eigen::Vector3f& point, const Eigen::Vector3f& centre, const Eigen::Vector3f& normal,
                   float voxel, float footprint) {
  if (footprint * kMinPixelsForEdges > voxel) return false;
  int axis = 0;
  normal.cwiseAbs().maxCoeff(&axis);
  const Eigen::Vector3f local = (point - centre) / voxel;
  const float reach = 0.5f - 0.75f * footprint / voxel;
  for (int a = 0; a < 3; ++a) {
    if (a != axis && std::abs(local[a]) > reach) return true;
  }
  return false;
}

}  // namespace

Rgb height_color(float z, const HeightRange& heights) {
  // Dark blue-grey at the floor through teal and green to pale sand at the
  // top of the walls: ordered in lightness, so it reads in grey too.
  static constexpr std::array<Rgb, 4> kRamp{
      {{55, 65, 110}, {40, 135, 140}, {130, 190, 100}, {240, 225, 160}}};
  const float span = std::max(heights.high - heights.low, 1e-6f);
  const float s = std::clamp((z - heights.low) / span, 0.0f, 1.0f) * static_cast<float>(kRamp.size() - 1);
  const auto i = std::min(static_cast<std::size_t>(s), kRamp.size() - 2);
  const float f = s - static_cast<float>(i);
  const auto mix = [f](std::uint8_t a, std::uint8_t b) {
    return static_cast<std::uint8_t>(std::lround(static_cast<float>(a) + f * (static_cast<float>(b) - a)));
  };
  return {mix(kRamp[i].r, kRamp[i + 1].r), mix(kRamp[i].g, kRamp[i + 1].g), mix(kRamp[i].b, kRamp[i + 1].b)};
}

VoxelViews render_voxel_views(const VoxelScene& scene, const VoxelSet& voxels, const Camera& camera,
                              const HeightRange& heights) {
  VoxelViews views{RgbImage(camera.width(), camera.height(), kBackground),
                   RgbImage(camera.width(), camera.height(), kBackground)};
  tbb::parallel_for(tbb::blocked_range<int>(0, camera.height()), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < camera.width(); ++x) {
        const Camera::Ray ray = camera.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
        const VoxelScene::Hit hit = scene.trace(ray);
        if (!hit.hit) continue;
        const Eigen::Vector3f& centre = voxels.centres[hit.voxel];
        float shade = face_shade(hit.normal);
        const Eigen::Vector3f point = ray.origin + hit.t * ray.direction;
        if (on_voxel_edge(point, centre, hit.normal, voxels.voxel, camera.pixel_footprint(hit.t))) {
          shade *= kEdgeShade;
        }
        views.metric.set(x, y, scaled(height_color(centre.z(), heights), shade));
        views.semantic.set(x, y, scaled(class_info(voxels.labels[hit.voxel]).color, shade));
      }
    }
  });
  return views;
}

}  // namespace sarmap::render
