// The 3-D pictures of the maps, as paper 000's figures pair them: the metric
// map (occupied voxels coloured by height) and the semantic map (the same
// voxels in their class colours, engine/core/classes.hpp), from one camera.
// One ray per pixel, cast once for both; faces shaded by their normal and
// voxel edges drawn where a voxel spans several pixels.
#pragma once

#include "engine/core/classes.hpp"
#include "engine/render/camera.hpp"
#include "engine/render/rgb_image.hpp"
#include "engine/render/voxel_scene.hpp"

namespace sarmap::render {

struct VoxelViews {
  RgbImage metric;
  RgbImage semantic;
};

inline constexpr Rgb kBackground{255, 255, 255};

// The heights the metric view's colour ramp spans (its ends clamp).
struct HeightRange {
  float low = 0;
  float high = 1;
};

// Casts every row in parallel (oneTBB); the pictures do not depend on the
// thread count.
VoxelViews render_voxel_views(const VoxelScene& scene, const VoxelSet& voxels, const Camera& camera,
                              const HeightRange& heights);

// The metric view's colour for a height within the range.
Rgb height_color(float z, const HeightRange& heights);

}  // namespace sarmap::render
