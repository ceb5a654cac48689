// The topological map: places the robot can stand (nodes) joined by drives it
// can make (edges), kept up to date as the segments and the metric map grow.
// Nodes come from node placement; a node's id never changes once given (a
// place that stops qualifying is retired, and revived with its id if it
// qualifies again). Candidate edges join nodes within a radius; an edge
// passes when no wall lies in the way at the robot's body heights (Embree)
// and the ground along it is seen, with no drop and no climb steeper than
// allowed. The passing edges are the roadmap; Kruskal's spanning forest over
// them is the tree the thesis plans on.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/metric/metric_map.hpp"
#include "engine/segments/segment_map.hpp"
#include "engine/topo/ground_profile.hpp"
#include "engine/topo/node_placement.hpp"
#include "engine/topo/topo_settings.hpp"
#include "engine/topo/traversability_grid.hpp"
#include "engine/topo/voxel_columns.hpp"
#include "engine/topo/wall_scene.hpp"

namespace sarmap::topo {

struct TopoNode {
  std::uint32_t id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // on the surface
  NodeKind kind = NodeKind::Terrain;
  std::uint32_t segment = 0;
  bool alive = true;
  PlaceKey key;
};

struct TopoEdge {
  std::uint32_t a = 0, b = 0;  // node ids, a < b
  double length = 0;           // straight 3-D distance, metres: the edge's weight
  double slope_deg = 0;
  ClassId ground = ClassId::Unknown;
  bool in_tree = false;
};

// What one update did, for the profile's counters.
struct TopoUpdate {
  std::size_t nodes = 0, nodes_added = 0, nodes_retired = 0;
  std::size_t candidates = 0, edges = 0, tree_edges = 0, components = 0;
  std::size_t rejected_wall = 0, rejected_drop = 0, rejected_steep = 0, rejected_unknown = 0;
  std::size_t wall_boxes = 0;
};

class TopoMap {
 public:
  // Throws sarmap::Error (InvalidArgument) for bad settings.
  explicit TopoMap(const TopoSettings& settings = {});
  ~TopoMap();
  TopoMap(TopoMap&&) noexcept;
  TopoMap& operator=(TopoMap&&) noexcept;

  // Rebuilds the grid, the wall scene, the nodes and edges from the current
  // segments and metric map. `changed` bounds where the map changed since the
  // last update (a scan's points and origin), so only voxels there are read
  // again; null reads the whole map. Deterministic for any thread count.
  TopoUpdate update(const segments::SegmentMap& segments, const metric::MetricMap& map,
                    const Bounds* changed = nullptr);

  // A map saved by a run (graph.json's nodes and edges) on the segments and
  // metric map it was built from, for planning without re-running.
  static TopoMap restore(const TopoSettings& settings, std::vector<TopoNode> nodes, std::vector<TopoEdge> edges,
                         const std::vector<const segments::Segment*>& segments, const metric::MetricMap& map);

  // Nodes, edges and the last update's counts, for a checkpoint
  // (engine/core/state_stream.hpp); the grid and wall scene are derived.
  void save_state(StateWriter& out) const;
  // Replaces nodes and edges with saved ones and derives the rest from the
  // maps they were saved with, so the next update() continues as the saved
  // map's would. Throws sarmap::Error (Parse) naming the offset for a stream
  // that holds no topological map; this map is unchanged then.
  void load_state(StateReader& in, const segments::SegmentMap& segments, const metric::MetricMap& map);

  const TopoSettings& settings() const { return settings_; }
  // Every node ever given an id, indexed by it (retired ones have alive = false).
  const std::vector<TopoNode>& nodes() const { return nodes_; }
  // The roadmap: every passing edge, sorted by (a, b); in_tree marks the spanning forest.
  const std::vector<TopoEdge>& edges() const { return edges_; }
  const TraversabilityGrid& grid() const { return grid_; }
  // The wall scene of the last update; nullptr before the first.
  const WallScene* walls() const { return walls_.get(); }

  // Bytes the map holds outside Embree: nodes, edges, the grid, the cached
  // voxel columns, the wall scene and the arrays kept between updates, by
  // capacity (the wall scene's Embree index: geometry::embree_bytes()). The
  // topo stage's per-map state, reported beside the metric map's.
  std::size_t memory_bytes() const;

  // Whether a straight drive between two stand points passes (walls, drops,
  // climbs, unknown ground), with the ground it crosses.
  GroundProfile check_drive(const Eigen::Vector3d& from, const Eigen::Vector3d& to) const;

 private:
  void connect();

  TopoSettings settings_;
  std::vector<TopoNode> nodes_;
  std::vector<TopoEdge> edges_;
  TraversabilityGrid grid_;
  OccupiedVoxelCache voxels_;
  VoxelColumns columns_;  // the last update's, kept for their arrays
  TraversabilityScratch grid_scratch_;
  std::unique_ptr<WallScene> walls_;
  TopoUpdate last_;
};

}  // namespace sarmap::topo
