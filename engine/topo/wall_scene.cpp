#include "engine/topo/wall_scene.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "engine/core/error.hpp"
#include "engine/geometry/segment_box.hpp"
#include "engine/topo/voxel_wall_boxes.hpp"

namespace sarmap::topo {
namespace {

constexpr double kBoxCell = 1.0;

std::int64_t box_cell(double v) { return static_cast<std::int64_t>(std::floor(v / kBoxCell)); }

std::uint64_t cell_key(std::int64_t x, std::int64_t y) {
  return (static_cast<std::uint64_t>(x + (std::int64_t{1} << 31)) << 32) |
         static_cast<std::uint32_t>(y + (std::int64_t{1} << 31));
}

geometry::OrientedBox segment_box(const segments::Segment& s, double grow) {
  geometry::OrientedBox box;
  box.center = s.rectangle.center;
  box.axes.col(0) = s.rectangle.axes[0];
  box.axes.col(1) = s.rectangle.axes[1];
  box.axes.col(2) = s.plane.normal;
  box.half_extents = {s.rectangle.half_extents[0] + grow, s.rectangle.half_extents[1] + grow,
                      s.thickness / 2 + grow};
  return box;
}

}  // namespace

WallScene::WallScene(const std::vector<const segments::Segment*>& segments, const VoxelColumns* columns,
                     const TopoSettings& settings)
    : settings_(settings) {
  validate(settings_);
  for (const segments::Segment* s : segments) {
    if (s->label == ClassId::Wall) boxes_.push_back(segment_box(*s, settings_.robot_radius));
  }
  segment_boxes_ = boxes_.size();
  if (columns != nullptr && settings_.obstacle_voxels) {
    for (const VoxelBox& box : merge_runs(obstacle_runs(*columns))) {
      boxes_.push_back(grown_box(box, columns->resolution, settings_.robot_radius));
    }
  }
  for (std::uint32_t b = 0; b < boxes_.size(); ++b) {
    const geometry::OrientedBox& box = boxes_[b];
    // The box's reach in x and y: |axes| times the half extents.
    const Eigen::Vector3d reach = box.axes.cwiseAbs() * box.half_extents;
    for (std::int64_t x = box_cell(box.center.x() - reach.x()); x <= box_cell(box.center.x() + reach.x()); ++x) {
      for (std::int64_t y = box_cell(box.center.y() - reach.y()); y <= box_cell(box.center.y() + reach.y()); ++y) {
        cells_[cell_key(x, y)].push_back(b);
      }
    }
  }
  // One mesh for all boxes: the scene is rebuilt often, and one merged mesh
  // builds several times faster than a mesh per box (bench/geometry).
  geometry::ClassedMesh walls;
  walls.label = ClassId::Wall;
  walls.name = "walls";
  for (const geometry::OrientedBox& box : boxes_) geometry::append_box(walls, box);
  scene_ = std::make_unique<geometry::TriangleScene>(std::span<const geometry::ClassedMesh>(&walls, 1),
                                                      geometry::BuildQuality::Low);
}

WallScene::~WallScene() = default;

bool WallScene::clear(const Eigen::Vector3d& stand) const {
  const auto it = cells_.find(cell_key(box_cell(stand.x()), box_cell(stand.y())));
  if (it == cells_.end()) return true;
  for (std::uint32_t b : it->second) {
    for (double h : settings_.body_heights) {
      if (geometry::signed_distance(stand + Eigen::Vector3d(0, 0, h), boxes_[b]) <= geometry::kSurfaceTolerance) return false;
    }
  }
  return true;
}

void WallScene::blocked(std::span<const StandPair> pairs, std::span<std::uint8_t> out) const {
  if (pairs.size() != out.size()) {
    throw Error(ErrorCode::InvalidArgument, "wall scene: one answer per stand pair is needed");
  }
  std::fill(out.begin(), out.end(), 0);
  if (pairs.empty() || boxes_.empty()) return;
  const std::size_t heights = settings_.body_heights.size();
  std::vector<geometry::Segment> rays(pairs.size() * heights);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    for (std::size_t h = 0; h < heights; ++h) {
      const Eigen::Vector3d lift(0, 0, settings_.body_heights[h]);
      rays[i * heights + h] = {pairs[i].from + lift, pairs[i].to + lift};
    }
  }
  std::vector<std::uint8_t> hit(rays.size());
  scene_->segments_blocked(rays, hit);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    for (std::size_t h = 0; h < heights; ++h) out[i] |= hit[i * heights + h];
  }
}

}  // namespace sarmap::topo
