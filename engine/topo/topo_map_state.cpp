// The topological map's part of a checkpoint. Only nodes (their ids, keys and
// positions are history: a node keeps its id through merges and retirement)
// and edges are saved; the voxel cache, grid and wall scene are functions of
// the segment and metric maps, which the checkpoint holds already.
#include <string>

#include "engine/topo/topo_map.hpp"

namespace sarmap::topo {

void TopoMap::save_state(StateWriter& out) const {
  out.tag("TOPO");
  out.put<std::uint64_t>(nodes_.size());
  for (const TopoNode& n : nodes_) {
    out.put(n.id);
    out.put(n.position.x()), out.put(n.position.y()), out.put(n.position.z());
    out.put(n.kind);
    out.put(n.segment);
    out.put<std::uint8_t>(n.alive);
    out.put(n.key.type);
    out.put(n.key.a), out.put(n.key.b), out.put(n.key.c);
  }
  out.put<std::uint64_t>(edges_.size());
  for (const TopoEdge& e : edges_) {
    out.put(e.a), out.put(e.b);
    out.put(e.length), out.put(e.slope_deg);
    out.put(e.ground);
    out.put<std::uint8_t>(e.in_tree);
  }
  out.put(last_);
}

void TopoMap::load_state(StateReader& in, const segments::SegmentMap& segment_map, const metric::MetricMap& map) {
  in.expect_tag("TOPO");
  std::vector<TopoNode> nodes(in.get_count(59));
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    TopoNode& n = nodes[i];
    n.id = in.get<std::uint32_t>();
    if (n.id != i) in.fail("topological node " + std::to_string(i) + " holds id " + std::to_string(n.id));
    const auto x = in.get<double>(), y = in.get<double>(), z = in.get<double>();
    n.position = {x, y, z};
    n.kind = in.get<NodeKind>();
    if (static_cast<unsigned>(n.kind) > static_cast<unsigned>(NodeKind::RampTop)) in.fail("bad node kind");
    n.segment = in.get<std::uint32_t>();
    n.alive = in.get<std::uint8_t>() != 0;
    n.key.type = in.get<PlaceKey::Type>();
    if (static_cast<unsigned>(n.key.type) > static_cast<unsigned>(PlaceKey::Type::Top)) in.fail("bad place key");
    n.key.a = in.get<std::int64_t>(), n.key.b = in.get<std::int64_t>(), n.key.c = in.get<std::int64_t>();
  }
  std::vector<TopoEdge> edges(in.get_count(26));
  for (TopoEdge& e : edges) {
    e.a = in.get<std::uint32_t>(), e.b = in.get<std::uint32_t>();
    if (e.a >= e.b || e.b >= nodes.size()) in.fail("an edge joins nodes that do not exist");
    e.length = in.get<double>(), e.slope_deg = in.get<double>();
    e.ground = in.get<ClassId>();
    if (static_cast<std::size_t>(e.ground) >= kClassCount) in.fail("bad edge ground class");
    e.in_tree = in.get<std::uint8_t>() != 0;
  }
  const auto last = in.get<TopoUpdate>();

  OccupiedVoxelCache voxels;
  voxels.refresh(map, nullptr);
  const VoxelColumns columns = voxels.columns(map.resolution());
  TraversabilityGrid grid = traversability_grid(columns, settings_);
  auto walls = std::make_unique<WallScene>(segment_map.segments(), &columns, settings_);
  nodes_ = std::move(nodes);
  edges_ = std::move(edges);
  last_ = last;
  voxels_ = std::move(voxels);
  grid_ = std::move(grid);
  walls_ = std::move(walls);
}

}  // namespace sarmap::topo
