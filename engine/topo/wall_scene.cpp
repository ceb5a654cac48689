#include "engine/topo/wall_scene.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/error.hpp"
#include "engine/core/vector_headroom.hpp"
#include "engine/geometry/segment_box.hpp"

namespace sarmap::topo {
namespace {

constexpr double kBoxCell = 1.0;

std::int32_t floor_div(std::int32_t a, std::int32_t b) { return a / b - (a % b != 0 && (a < 0) != (b < 0)); }

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
  add_mesh();  // the segments' boxes
}

WallScene::WallScene(const std::vector<const segments::Segment*>& segments, const VoxelColumns* columns,
                     const TopoSettings& settings)
    : WallScene(settings) {
  rebuild(segments, columns);
}

void WallScene::rebuild(const std::vector<const segments::Segment*>& segments, const VoxelColumns* columns,
                        const ColumnRect* changed) {
  meshes_[0].vertices.clear();
  meshes_[0].indices.clear();
  boxes_.clear();
  for (const segments::Segment* s : segments) {
    if (s->label == ClassId::Wall) {
      boxes_.push_back(segment_box(*s, settings_.robot_radius));
      geometry::append_box(meshes_[0], boxes_.back());
    }
  }
  segment_boxes_ = boxes_.size();
  ++build_;
  if (columns != nullptr && settings_.obstacle_voxels && columns->width > 0 && columns->height > 0) {
    add_tile_boxes(*columns, changed);
  }
  // Tiles this build did not reach (beyond the columns, or their boxes gone)
  // hold none, and no storage: their region's walls are gone (a bounded
  // map's forgotten blocks), and kept storage would grow with the area ever
  // seen. The scene lets go of their geometries (TriangleScene::rebuild).
  for (std::size_t m = 1; m < meshes_.size(); ++m) {
    if (tiles_[m].seen == build_) continue;
    release_storage(tiles_[m].boxes);
    release_storage(meshes_[m].vertices);
    release_storage(meshes_[m].indices);
  }
  index_cells();
  if (scene_ == nullptr) {
    scene_ = std::make_unique<geometry::TriangleScene>(meshes_, geometry::BuildQuality::Low);
  } else {
    scene_->rebuild(meshes_);
  }
}

void WallScene::add_tile_boxes(const VoxelColumns& columns, const ColumnRect* changed) {
  const std::int32_t tx0 = floor_div(columns.x0, kTileColumns);
  const std::int32_t tx1 = floor_div(columns.x0 + columns.width - 1, kTileColumns);
  const std::int32_t ty0 = floor_div(columns.y0, kTileColumns);
  const std::int32_t ty1 = floor_div(columns.y0 + columns.height - 1, kTileColumns);
  for (std::int32_t ty = ty0; ty <= ty1; ++ty) {
    for (std::int32_t tx = tx0; tx <= tx1; ++tx) {
      const ColumnRect tile{tx * kTileColumns, tx * kTileColumns + kTileColumns - 1, ty * kTileColumns,
                            ty * kTileColumns + kTileColumns - 1};
      const std::uint32_t* known = tile_mesh_.find(cell_key(tx, ty));
      const bool unchanged = changed != nullptr && !changed->meets(tile);
      if (unchanged && known == nullptr) continue;  // held no boxes, and its columns are as they were
      if (!unchanged) {
        obstacle_runs(columns, tile, runs_);
        if (runs_.empty()) continue;  // a mesh it had is emptied below, as not seen in this build
        merge_runs(runs_, merge_scratch_, voxel_boxes_);
        // A tile keeps its mesh for the scene's life: unchanged, it is not built again.
        const auto [at, added] =
            tile_mesh_.try_emplace(cell_key(tx, ty), static_cast<std::uint32_t>(meshes_.size()));
        if (added) add_mesh();
        Tile& fresh = tiles_[tile_mesh_.values()[at]];
        geometry::ClassedMesh& mesh = meshes_[tile_mesh_.values()[at]];
        fresh.boxes.clear();
        mesh.vertices.clear();
        mesh.indices.clear();
        reserve_with_headroom(mesh.vertices, 8 * voxel_boxes_.size());
        reserve_with_headroom(mesh.indices, 36 * voxel_boxes_.size());
        for (const VoxelBox& box : voxel_boxes_) {
          fresh.boxes.push_back(grown_box(box, columns.resolution, settings_.robot_radius));
          geometry::append_box(mesh, fresh.boxes.back());
        }
        known = &tile_mesh_.values()[at];
      }
      Tile& tile_boxes = tiles_[*known];
      tile_boxes.seen = build_;
      boxes_.insert(boxes_.end(), tile_boxes.boxes.begin(), tile_boxes.boxes.end());
    }
  }
}

void WallScene::index_cells() {
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
}

void WallScene::add_mesh() {
  geometry::ClassedMesh& mesh = meshes_.emplace_back();
  mesh.label = ClassId::Wall;
  mesh.name = "walls";
  tiles_.emplace_back();
}

WallScene::~WallScene() = default;

std::size_t WallScene::memory_bytes() const {
  std::size_t bytes = capacity_bytes(boxes_) + cell_index_.memory_bytes() + capacity_bytes(cell_start_) +
                      capacity_bytes(cell_boxes_) + capacity_bytes(meshes_) + capacity_bytes(tiles_) +
                      tile_mesh_.memory_bytes() + capacity_bytes(runs_) + capacity_bytes(voxel_boxes_) +
                      merge_scratch_.memory_bytes();
  for (const geometry::ClassedMesh& m : meshes_) bytes += capacity_bytes(m.vertices) + capacity_bytes(m.indices);
  for (const Tile& t : tiles_) bytes += capacity_bytes(t.boxes);
  if (scene_) bytes += sizeof(geometry::TriangleScene) + scene_->memory_bytes();
  return bytes;
}

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
