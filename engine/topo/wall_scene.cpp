#include "engine/topo/wall_scene.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "engine/core/error.hpp"
#include "engine/core/vector_headroom.hpp"
#include "engine/geometry/segment_box.hpp"

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

WallScene::WallScene(const TopoSettings& settings) : settings_(settings) {
  validate(settings_);
  mesh_.label = ClassId::Wall;
  mesh_.name = "walls";
}

WallScene::WallScene(const std::vector<const segments::Segment*>& segments, const VoxelColumns* columns,
                     const TopoSettings& settings)
    : WallScene(settings) {
  rebuild(segments, columns);
}

void WallScene::rebuild(const std::vector<const segments::Segment*>& segments, const VoxelColumns* columns) {
  voxel_boxes_.clear();
  if (columns != nullptr && settings_.obstacle_voxels) {
    obstacle_runs(*columns, runs_);
    merge_runs(runs_, merge_scratch_, voxel_boxes_);
  }
  boxes_.clear();
  reserve_with_headroom(boxes_, segments.size() + voxel_boxes_.size());
  for (const segments::Segment* s : segments) {
    if (s->label == ClassId::Wall) boxes_.push_back(segment_box(*s, settings_.robot_radius));
  }
  segment_boxes_ = boxes_.size();
  for (const VoxelBox& box : voxel_boxes_) boxes_.push_back(grown_box(box, columns->resolution, settings_.robot_radius));

  // The cells each box's bounding box touches, counted, then listed.
  const auto for_each_cell = [&](const geometry::OrientedBox& box, auto&& visit) {
    // The box's reach in x and y: |axes| times the half extents.
    const Eigen::Vector3d reach = box.axes.cwiseAbs() * box.half_extents;
    for (std::int64_t x = box_cell(box.center.x() - reach.x()); x <= box_cell(box.center.x() + reach.x()); ++x) {
      for (std::int64_t y = box_cell(box.center.y() - reach.y()); y <= box_cell(box.center.y() + reach.y()); ++y) {
        visit(cell_key(x, y));
      }
    }
  };
  cell_index_.clear();
  for (const geometry::OrientedBox& box : boxes_) {
    for_each_cell(box, [&](std::uint64_t key) { ++cell_index_[key]; });
  }
  std::vector<std::uint32_t>& counts = cell_index_.values();
  cell_start_.assign(counts.size() + 1, 0);
  for (std::size_t c = 0; c < counts.size(); ++c) {
    cell_start_[c + 1] = cell_start_[c] + counts[c];
    counts[c] = cell_start_[c];  // from here on, where the cell's next box goes
  }
  cell_boxes_.resize(cell_start_.back());
  for (std::uint32_t b = 0; b < boxes_.size(); ++b) {
    for_each_cell(boxes_[b], [&](std::uint64_t key) { cell_boxes_[(*cell_index_.find(key))++] = b; });
  }

  // One mesh for all boxes: the scene is rebuilt often, and one merged mesh
  // builds several times faster than a mesh per box (bench/geometry).
  mesh_.vertices.clear();
  mesh_.indices.clear();
  reserve_with_headroom(mesh_.vertices, 8 * boxes_.size());
  reserve_with_headroom(mesh_.indices, 36 * boxes_.size());
  for (const geometry::OrientedBox& box : boxes_) geometry::append_box(mesh_, box);
  const std::span<const geometry::ClassedMesh> meshes(&mesh_, 1);
  if (scene_ == nullptr) {
    scene_ = std::make_unique<geometry::TriangleScene>(meshes, geometry::BuildQuality::Low);
  } else {
    scene_->rebuild(meshes);
  }
}

WallScene::~WallScene() = default;

bool WallScene::clear(const Eigen::Vector3d& stand) const {
  const std::uint32_t cell = cell_index_.index_of(cell_key(box_cell(stand.x()), box_cell(stand.y())));
  if (cell == FlatKeyMap<std::uint32_t>::kAbsent) return true;
  for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
    const std::uint32_t b = cell_boxes_[k];
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
