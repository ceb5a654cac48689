// The walls an edge of the topological map must not pass through, in one
// Embree scene: every wall segment as a box around its rectangle, plus the
// occupied voxels of class wall or other (vertical runs of columns, merged
// where neighbours share extents: engine/topo/voxel_wall_boxes.hpp), all
// grown by the robot's radius. Voxel boxes are merged within tiles of
// kTileColumns x kTileColumns columns, a mesh per tile, so that a rebuild
// builds again only the tiles whose boxes changed (Embree's two-level index);
// the split keeps the same solid, as a grown box is the box's Minkowski sum
// with a cube and the union of such sums is the sum of the union. An edge is
// tested as occluded rays between its two stand points at each of the robot's
// body heights, in parallel batches.
// (The sides of platforms and ramps are not walls here: low at a ramp's foot,
// they are drops, which the ground profile finds.)
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "engine/core/flat_key_map.hpp"
#include "engine/geometry/oriented_box.hpp"
#include "engine/geometry/triangle_scene.hpp"
#include "engine/topo/voxel_columns.hpp"
#include "engine/segments/segment.hpp"
#include "engine/topo/topo_settings.hpp"
#include "engine/topo/voxel_wall_boxes.hpp"

namespace sarmap::topo {

// A straight drive between two stand points on the ground.
struct StandPair {
  Eigen::Vector3d from, to;
};

class WallScene {
 public:
  // A scene of no walls, for rebuild(). Throws sarmap::Error for bad settings.
  explicit WallScene(const TopoSettings& settings);
  // `columns` may be null (no voxels), and voxels are used only when
  // settings.obstacle_voxels is set. Throws sarmap::Error for bad settings.
  WallScene(const std::vector<const segments::Segment*>& segments, const VoxelColumns* columns,
            const TopoSettings& settings);
  ~WallScene();

  // Becomes the scene of these segments and columns, as made by the
  // constructor, on the arrays and Embree scene of the last build: the
  // topological map rebuilds its walls at every update, and a whole-map
  // scene's arrays made anew each time fragmented the heap of long runs.
  // `changed` (voxel indices), when given, holds every column that differs
  // from the last build's columns: the tiles it does not meet keep their
  // boxes. Throws as the constructor does; the scene must not be used after
  // a throw.
  void rebuild(const std::vector<const segments::Segment*>& segments, const VoxelColumns* columns,
               const ColumnRect* changed = nullptr);

  // Whether a robot standing here is clear of every (grown) box at each body
  // height, by more than the scene's float tolerance: a place on a box's
  // surface would have every drive from it blocked.
  bool clear(const Eigen::Vector3d& stand) const;

  // blocked[i] = 1 when the drive pairs[i] meets a wall at any body height.
  // Deterministic on any thread count; allocation proportional to the batch.
  void blocked(std::span<const StandPair> pairs, std::span<std::uint8_t> blocked) const;

  // Voxel boxes are merged within tiles of this many columns a side.
  static constexpr std::int32_t kTileColumns = 64;

  // The grown boxes in the scene (segments first, then voxel boxes tile by tile).
  const std::vector<geometry::OrientedBox>& boxes() const { return boxes_; }
  std::size_t segment_boxes() const { return segment_boxes_; }

  // Bytes held outside Embree: the boxes, tiles, meshes, cell index and the
  // arrays kept between builds, by capacity (Embree's part:
  // geometry::embree_bytes()).
  std::size_t memory_bytes() const;

 private:
  TopoSettings settings_;
  std::vector<geometry::OrientedBox> boxes_;
  std::size_t segment_boxes_ = 0;
  std::unique_ptr<geometry::TriangleScene> scene_;
  // Boxes by the cells (kBoxCell metres) their bounding boxes touch, for
  // clear(): cell i's boxes are cell_boxes_[cell_start_[i] .. cell_start_[i + 1]),
  // cells numbered in cell_index_.
  FlatKeyMap<std::uint32_t> cell_index_;
  std::vector<std::uint32_t> cell_start_, cell_boxes_;
  // Each tile's boxes (merged again where `changed` meets it, or all of them
  // without it) appended to boxes_, the tiles reached marked with build_.
  void add_tile_boxes(const VoxelColumns& columns, const ColumnRect* changed);
  // cell_index_, cell_start_ and cell_boxes_ of boxes_.
  void index_cells();
  void add_mesh();

  // A tile's grown voxel boxes, and the build that last reached it.
  struct Tile {
    std::vector<geometry::OrientedBox> boxes;
    std::uint64_t seen = 0;
  };
  // Mesh 0 holds the segments' boxes, the others a tile's each (empty while
  // the tile holds none), numbered in tile_mesh_; tiles_ by the same number.
  std::vector<geometry::ClassedMesh> meshes_;
  std::vector<Tile> tiles_;
  FlatKeyMap<std::uint32_t> tile_mesh_;
  std::uint64_t build_ = 0;
  // Kept between builds for their storage.
  std::vector<VoxelBox> runs_, voxel_boxes_;
  BoxMergeScratch merge_scratch_;
};

}  // namespace sarmap::topo
