// The top-down picture: the occupied voxels seen from straight above in
// their class colours, washed out so what is drawn over them stands out: the
// segments' rectangles, the topological graph (roadmap edges grey, spanning
// tree black, nodes by the ground they stand on) and a planned path.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "engine/render/camera.hpp"
#include "engine/render/rgb_image.hpp"
#include "engine/render/voxel_scene.hpp"
#include "engine/segments/segment.hpp"
#include "engine/topo/topo_map.hpp"

namespace sarmap::render {

// What the top view draws over the map; any part may be empty.
struct MapOverlays {
  std::vector<segments::Segment> segments;
  std::vector<topo::TopoNode> nodes;  // only alive nodes are drawn
  std::vector<topo::TopoEdge> edges;  // between alive nodes
  std::vector<Eigen::Vector3d> path;  // a route's points, in order
};

inline constexpr Rgb kPathColor{0, 170, 60};
inline constexpr Rgb kTreeEdgeColor{0, 0, 0};
inline constexpr Rgb kRoadmapEdgeColor{150, 150, 150};

// The map from `camera` (top_down_camera of the voxels' box), then the overlays.
RgbImage render_top_view(const VoxelScene& scene, const VoxelSet& voxels, const Camera& camera,
                         const MapOverlays& overlays);

// Draws the overlays through `camera`'s projection; line widths and node
// sizes scale with the image.
void draw_overlays(RgbImage& image, const Camera& camera, const MapOverlays& overlays);

}  // namespace sarmap::render
