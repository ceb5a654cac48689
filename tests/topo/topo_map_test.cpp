// The topological map on the hand-built world of synthetic_world.hpp: the
// traversability grid, drives against walls and drops, node placement, the
// roadmap and tree, routes and their reasons, and the files.
#include "engine/topo/topo_map.hpp"

#include <cstring>
#include <fstream>
#include <set>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "engine/core/error.hpp"
#include "engine/geometry/oriented_box.hpp"
#include "engine/geometry/segment_box.hpp"
#include "engine/topo/graph_files.hpp"
#include "engine/topo/ros_map_files.hpp"
#include "engine/topo/route_planner.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/topo/synthetic_world.hpp"

namespace sarmap::topo {
namespace {

using testing::world_map;
using testing::world_segments;

struct World {
  metric::MetricMap map = world_map();
  segments::SegmentMap segments = world_segments();
  TopoMap topo;
  TopoUpdate update;
  World() {
    update = topo.update(segments, map);
    if (const char* dump = std::getenv("SARMAP_TEST_DUMP")) {
      write_graph_json(std::filesystem::path(dump) / "graph.json", topo);
      write_ros_map(topo.grid().grid, dump, "grid");
    }
  }
};

const World& world() {
  static const World w;
  return w;
}

CellState cell_state(const TopoMap& t, double x, double y) { return t.grid().grid.at(t.grid().grid.cell_at({x, y})); }

TEST(TraversabilityGrid, FloorWallsPlatformAndTheirMargins) {
  const TopoMap& t = world().topo;
  EXPECT_EQ(cell_state(t, 1.0, 1.5), CellState::Free);
  EXPECT_NEAR(t.grid().ground_at(t.grid().grid.cell_at({1.0, 1.5})), -0.025, 1e-6);
  EXPECT_EQ(cell_state(t, 2.0, 0.5), CellState::Occupied);   // the wall
  EXPECT_EQ(cell_state(t, 1.82, 0.5), CellState::Occupied);  // within the robot's radius of it
  EXPECT_EQ(cell_state(t, 1.70, 0.5), CellState::Free);
  EXPECT_EQ(cell_state(t, 2.0, 1.5), CellState::Free);       // the doorway's middle
  EXPECT_EQ(cell_state(t, 3.4, 0.8), CellState::Free);       // the platform's top
  EXPECT_NEAR(t.grid().ground_at(t.grid().grid.cell_at({3.4, 0.8})), 0.275, 1e-6);
  EXPECT_EQ(cell_state(t, 3.02, 0.8), CellState::Occupied);  // its rim: a drop
  EXPECT_TRUE(t.grid().near_drop[t.grid().grid.index_of(t.grid().grid.cell_at({2.9, 0.8}))]);
  EXPECT_FALSE(t.grid().near_drop[t.grid().grid.index_of(t.grid().grid.cell_at({1.8, 0.5}))]);  // a wall, not a drop
}

TEST(TopoMap, DrivesThroughTheDoorwayButNotTheWallOrOffThePlatform) {
  const TopoMap& t = world().topo;
  EXPECT_EQ(t.check_drive({1.2, 1.5, 0}, {2.8, 1.5, 0}).verdict, DriveVerdict::Passes);
  EXPECT_EQ(t.check_drive({1.2, 0.5, 0}, {2.8, 0.5, 0}).verdict, DriveVerdict::Wall);
  EXPECT_EQ(t.check_drive({1.2, 1.5, 0}, {2.8, 2.3, 0}).verdict, DriveVerdict::Wall);  // clips the door's frame
  EXPECT_EQ(t.check_drive({3.4, 0.8, 0.3}, {3.4, 2.0, 0}).verdict, DriveVerdict::Drop);
  EXPECT_EQ(t.check_drive({2.6, 0.3, 0}, {2.6, 2.5, 0}).verdict, DriveVerdict::Passes);
  EXPECT_EQ(t.check_drive({2.85, 0.3, 0}, {2.85, 2.5, 0}).verdict, DriveVerdict::Drop);  // grazes the platform
  EXPECT_EQ(t.check_drive({3.5, 2.0, 0}, {5.5, 2.0, 0}).verdict, DriveVerdict::Unknown);  // off the seen floor
}

TEST(TopoMap, NodesStandOnTheLatticeClearOfWallsAndDrops) {
  const TopoMap& t = world().topo;
  std::size_t floor = 0, platform = 0, nudged = 0;
  for (const TopoNode& n : t.nodes()) {
    ASSERT_TRUE(n.alive);
    EXPECT_EQ(t.grid().grid.at(t.grid().grid.cell_at(n.position.head<2>())), CellState::Free) << n.id;
    if (n.kind == NodeKind::FlatRamp) {
      ++platform;
      EXPECT_NEAR(n.position.z(), 0.3, 1e-3);
    } else {
      ++floor;
      EXPECT_EQ(n.kind, NodeKind::Terrain);
      EXPECT_NEAR(n.position.z(), 0.0, 1e-3);
    }
    if (n.key.type == PlaceKey::Type::Lattice) {
      // On its lattice point, or nudged at most a third of the pitch off it.
      const Eigen::Vector2d lattice(0.75 * static_cast<double>(n.key.a), 0.75 * static_cast<double>(n.key.b));
      EXPECT_LE((n.position.head<2>() - lattice).norm(), 0.25 + 1e-9) << n.id;
      nudged += (n.position.head<2>() - lattice).norm() > 1e-9;
    }
    for (const TopoNode& m : t.nodes()) {
      if (m.id != n.id) {
        EXPECT_GT((m.position - n.position).norm(), 0.75 / 3) << n.id << " " << m.id;
      }
    }
  }
  EXPECT_EQ(platform, 1u);
  EXPECT_GE(floor, 20u);
  EXPECT_GT(nudged, 0u);  // by the door frames, the platform and the floor's edge
}

TEST(TopoMap, NoEdgeCrossesAWallAndThePlatformStaysApart) {
  const TopoMap& t = world().topo;
  ASSERT_FALSE(t.edges().empty());
  bool through_door = false;
  for (const TopoEdge& e : t.edges()) {
    const TopoNode& a = t.nodes()[e.a];
    const TopoNode& b = t.nodes()[e.b];
    EXPECT_NEAR(e.length, (a.position - b.position).norm(), 1e-12);
    for (const testing::Solid& s : testing::world_solids()) {
      geometry::OrientedBox box;
      box.center = (s.min + s.max) / 2;
      box.half_extents = (s.max - s.min) / 2;
      for (double h : t.settings().body_heights) {
        const geometry::Segment drive{a.position + Eigen::Vector3d(0, 0, h), b.position + Eigen::Vector3d(0, 0, h)};
        EXPECT_FALSE(geometry::segment_intersects_box(drive, box)) << e.a << "-" << e.b;
      }
    }
    EXPECT_EQ(a.kind == NodeKind::FlatRamp, b.kind == NodeKind::FlatRamp) << "an edge leaves the platform";
    through_door |= (a.position.x() < 2) != (b.position.x() < 2);
  }
  EXPECT_TRUE(through_door);
  EXPECT_GT(world().update.rejected_wall, 0u);
  EXPECT_GT(world().update.rejected_drop, 0u);
}

TEST(TopoMap, TreeIsASpanningForestOfTheRoadmap) {
  const TopoMap& t = world().topo;
  std::size_t tree = 0;
  for (const TopoEdge& e : t.edges()) tree += e.in_tree;
  // Two components: the floor (one room through the door) and the platform.
  EXPECT_EQ(world().update.components, 2u);
  EXPECT_EQ(tree, world().update.nodes - 2);
}

TEST(RoutePlanner, AcrossTheDoorwayOnEveryGraphAndSearch) {
  const TopoMap& t = world().topo;
  const Eigen::Vector3d from(0.6, 0.6, 0), to(3.4, 2.5, 0);
  double tree_cost = -1, roadmap_cost = -1;
  for (RouteGraph g : {RouteGraph::Tree, RouteGraph::Roadmap, RouteGraph::Grid}) {
    for (RouteSearch s : {RouteSearch::Dijkstra, RouteSearch::AStar}) {
      const Route r = plan_route(t, from, to, g, s);
      ASSERT_TRUE(r.found) << to_string(g) << " " << r.reason;
      EXPECT_GE(r.length, (to - from).norm());
      EXPECT_NEAR(r.points.front().x(), 0.6, 1e-12);
      EXPECT_NEAR(r.points.back().y(), 2.5, 1e-12);
      // Every step is a drive that passes.
      for (std::size_t i = 1; i < r.points.size(); ++i) {
        if (g != RouteGraph::Grid) {
          EXPECT_EQ(t.check_drive(r.points[i - 1], r.points[i]).verdict, DriveVerdict::Passes);
        }
      }
      if (g == RouteGraph::Tree) {
        if (tree_cost < 0) tree_cost = r.length;
        EXPECT_NEAR(r.length, tree_cost, 1e-9);  // Dijkstra and A* agree
      }
      if (g == RouteGraph::Roadmap) {
        if (roadmap_cost < 0) roadmap_cost = r.length;
        EXPECT_NEAR(r.length, roadmap_cost, 1e-9);
      }
    }
  }
  EXPECT_LE(roadmap_cost, tree_cost + 1e-9);
}

TEST(RoutePlanner, ReasonsWhenThereIsNoPath) {
  const TopoMap& t = world().topo;
  for (RouteGraph g : {RouteGraph::Tree, RouteGraph::Roadmap, RouteGraph::Grid}) {
    EXPECT_EQ(plan_route(t, {0.6, 0.6, 0}, {3.4, 0.8, 0.3}, g).reason, "unreachable") << to_string(g);
    EXPECT_EQ(plan_route(t, {2.0, 0.5, 0}, {0.6, 0.6, 0}, g).reason, "start_blocked") << to_string(g);
    EXPECT_EQ(plan_route(t, {0.6, 0.6, 0}, {2.0, 2.5, 0}, g).reason, "goal_blocked") << to_string(g);
    EXPECT_EQ(plan_route(t, {6.0, 1.0, 0}, {0.6, 0.6, 0}, g).reason, "unknown_space") << to_string(g);
    EXPECT_FALSE(plan_route(t, {0.6, 0.6, 0}, {3.4, 0.8, 0.3}, g).found);
  }
  EXPECT_THROW(plan_route(t, {std::nan(""), 0, 0}, {0, 0, 0}, RouteGraph::Tree), Error);
}

TEST(TopoMap, SameGraphOnOneAndTwoThreads) {
  auto build = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    TopoMap t;
    t.update(world_segments(), world_map());
    return graph_json(t);
  };
  EXPECT_EQ(build(1), build(2));
}

TEST(TopoMap, NodeIdsStayWhenTheMapGrows) {
  const metric::MetricMap map = world_map();
  segments::SegmentMap segments = world_segments();
  TopoMap t;
  t.update(segments, map);
  std::vector<TopoNode> before = t.nodes();
  // Grow the floor beyond x = 4 by 1.5 m: new nodes get new ids, old ones keep theirs.
  metric::MetricMap bigger = world_map();
  for (int i = 80; i < 110; ++i) {
    for (int j = 0; j < 60; ++j) {
      testing::set_voxel(bigger, {(i + 0.5) * 0.05, (j + 0.5) * 0.05, -0.025}, true, ClassId::Terrain);
      for (int k = 0; k < 20; ++k) testing::set_voxel(bigger, {(i + 0.5) * 0.05, (j + 0.5) * 0.05, (k + 0.5) * 0.05}, false, ClassId::Unknown);
    }
  }
  PointBuffer more;
  more.enable_labels();
  for (double x = 4.02; x <= 5.5; x += 0.02) {
    for (double y = 0; y <= 3.0; y += 0.02) {
      more.push_back(static_cast<float>(x), static_cast<float>(y), 0);
      more.labels()[more.size() - 1] = static_cast<std::uint8_t>(ClassId::Terrain);
    }
  }
  segments.integrate(more, {4.5, 1.5, 0.6});
  const TopoUpdate u = t.update(segments, bigger);
  EXPECT_GT(u.nodes_added, 0u);
  for (const TopoNode& old : before) {
    const TopoNode& now = t.nodes()[old.id];
    EXPECT_EQ(now.key, old.key);
    EXPECT_NEAR((now.position - old.position).head<2>().norm(), 0.0, 1e-12) << old.id;
  }
  for (std::size_t id = before.size(); id < t.nodes().size(); ++id) EXPECT_GT(t.nodes()[id].position.x(), 3.9);
}

// Updates that name where the map changed keep the grid equal to one made
// from the whole map: a room's floor seen beyond x = 4 (the grid grows),
// then a box on it.
TEST(TopoMap, GridUpdatedWhereTheMapChangedEqualsAGridFromTheWholeMap) {
  metric::MetricMap map = world_map();
  const segments::SegmentMap segments = world_segments();
  TopoMap t;
  t.update(segments, map);
  const auto expect_whole_grid = [&] {
    const TraversabilityGrid whole = traversability_grid(voxel_columns(map), t.settings());
    EXPECT_EQ(t.grid().grid.width(), whole.grid.width());
    EXPECT_EQ(t.grid().grid.height(), whole.grid.height());
    EXPECT_TRUE(std::equal(whole.grid.cells().begin(), whole.grid.cells().end(), t.grid().grid.cells().begin()));
    EXPECT_EQ(0, std::memcmp(whole.ground.data(), t.grid().ground.data(), whole.ground.size() * sizeof(float)));
    EXPECT_EQ(whole.near_drop, t.grid().near_drop);
  };
  Bounds changed;
  for (int i = 80; i < 110; ++i) {
    for (int j = 0; j < 60; ++j) {
      const Eigen::Vector3d floor((i + 0.5) * 0.05, (j + 0.5) * 0.05, -0.025);
      testing::set_voxel(map, floor, true, ClassId::Terrain);
      changed.extend(floor);
    }
  }
  t.update(segments, map, &changed);
  expect_whole_grid();
  Bounds box;
  for (double x = 4.6; x < 4.9; x += 0.05) {
    for (double z = 0.025; z < 0.3; z += 0.05) {
      testing::set_voxel(map, {x, 1.52, z}, true, ClassId::Other);
      box.extend({x, 1.52, z});
    }
  }
  const std::vector<CellState> before(t.grid().grid.cells().begin(), t.grid().grid.cells().end());
  t.update(segments, map, &box);
  expect_whole_grid();
  EXPECT_FALSE(std::equal(before.begin(), before.end(), t.grid().grid.cells().begin()));  // the box is in
}

TEST(GraphFiles, JsonRoundTripAndTheOtherFormats) {
  test::ScratchFolder dir;
  const TopoMap& t = world().topo;
  write_graph_json(dir / "graph.json", t);
  const GraphFile file = read_graph_json(dir / "graph.json");
  EXPECT_EQ(file.settings.node_spacing, t.settings().node_spacing);
  ASSERT_EQ(file.nodes.size(), t.nodes().size());
  ASSERT_EQ(file.edges.size(), t.edges().size());
  for (std::size_t i = 0; i < t.edges().size(); ++i) {
    EXPECT_EQ(file.edges[i].a, t.edges()[i].a);
    EXPECT_EQ(file.edges[i].in_tree, t.edges()[i].in_tree);
    EXPECT_EQ(file.edges[i].ground, t.edges()[i].ground);
  }
  // A route on the restored map is the same route.
  std::vector<const segments::Segment*> segs = world().segments.segments();
  const TopoMap restored = TopoMap::restore(file.settings, file.nodes, file.edges, segs, world().map);
  const Route a = plan_route(t, {0.6, 0.6, 0}, {3.4, 2.5, 0}, RouteGraph::Roadmap);
  const Route b = plan_route(restored, {0.6, 0.6, 0}, {3.4, 2.5, 0}, RouteGraph::Roadmap);
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(route_json(a), route_json(b));
  write_graph_graphml(dir / "graph.graphml", t);
  write_graph_ply(dir / "graph.ply", t);
  std::ifstream graphml(dir / "graph.graphml");
  const std::string xml((std::istreambuf_iterator<char>(graphml)), std::istreambuf_iterator<char>());
  std::size_t edges = 0;
  for (std::size_t at = xml.find("<edge "); at != std::string::npos; at = xml.find("<edge ", at + 1)) ++edges;
  EXPECT_EQ(edges, t.edges().size());
  EXPECT_NE(xml.find("attr.name=\"x\""), std::string::npos);
}

TEST(GraphFiles, BadFilesNameTheEntry) {
  test::ScratchFolder dir;
  write_graph_json(dir / "graph.json", world().topo);
  std::ifstream in(dir / "graph.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string bad = text.replace(text.find("\"length\""), 8, "\"lengthx\"");
  try {
    read_graph_json(dir.write("bad.json", bad));
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("links[0]: missing \"length\""), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_graph_json(dir.write("broken.json", "{")), Error);
}

TEST(RouteJson, FoundAndNotFound) {
  Route r;
  r.found = false;
  r.reason = "unreachable";
  r.graph = RouteGraph::Grid;
  const std::string j = route_json(r);
  EXPECT_NE(j.find("\"reason\": \"unreachable\""), std::string::npos) << j;
  EXPECT_NE(j.find("\"algorithm\": \"wavefront\""), std::string::npos) << j;
  EXPECT_EQ(j.find("\"nodes\""), std::string::npos);
}

TEST(RouteJson, ReadsBackWhatWasWritten) {
  test::ScratchFolder dir;
  Route r;
  r.found = true;
  r.graph = RouteGraph::Roadmap;
  r.search = RouteSearch::AStar;
  r.length = 2.5;
  r.points = {{0.5, 0.5, 0}, {1.5, 0.5, 0.25}, {2.5, 1, 0.3}};
  r.nodes = {4, 9};
  write_route_json(dir / "path.json", r);
  const Route back = read_route_json(dir / "path.json");
  EXPECT_TRUE(back.found);
  EXPECT_EQ(back.graph, RouteGraph::Roadmap);
  EXPECT_EQ(back.search, RouteSearch::AStar);
  EXPECT_DOUBLE_EQ(back.length, 2.5);
  ASSERT_EQ(back.points.size(), 3u);
  EXPECT_EQ(back.points[2], r.points[2]);
  EXPECT_EQ(back.nodes, r.nodes);

  Route none;
  none.reason = "unreachable";
  none.graph = RouteGraph::Grid;
  write_route_json(dir / "none.json", none);
  const Route none_back = read_route_json(dir / "none.json");
  EXPECT_FALSE(none_back.found);
  EXPECT_EQ(none_back.reason, "unreachable");
  EXPECT_EQ(none_back.graph, RouteGraph::Grid);
  EXPECT_TRUE(none_back.points.empty());

  try {
    read_route_json(dir.write(
        "bad.json",
        R"({"found": true, "graph": "tree", "algorithm": "dijkstra", "length": 1, "points": [[0, 0]], "nodes": []})"));
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("points[0]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(
      read_route_json(dir.write(
          "grid.json",
          R"({"found": false, "reason": "x", "graph": "grid", "algorithm": "astar", "length": 0, "points": []})")),
      Error);
}

}  // namespace
}  // namespace sarmap::topo

namespace sarmap::topo {
namespace {

bool same_columns(const VoxelColumns& a, const VoxelColumns& b) {
  return a.x0 == b.x0 && a.y0 == b.y0 && a.width == b.width && a.height == b.height && a.start == b.start &&
         a.z == b.z && a.label == b.label;
}

TEST(OccupiedVoxelCache, RescanningTheChangedRegionMatchesAFullRead) {
  metric::MetricMap map = world_map();
  OccupiedVoxelCache cache;
  cache.refresh(map, nullptr);
  EXPECT_TRUE(same_columns(cache.columns(map.resolution()), voxel_columns(map)));
  // A box appears on the floor and part of a wall is seen free: changes within one region.
  for (double x = 0.5; x < 0.8; x += 0.05) {
    for (double y = 0.5; y < 0.8; y += 0.05) testing::set_voxel(map, {x + 0.01, y + 0.01, 0.11}, true, ClassId::Other);
  }
  testing::set_voxel(map, {2.01, 0.51, 0.51}, false, ClassId::Unknown);
  Bounds changed;
  changed.extend({0.4, 0.4, 0});
  changed.extend({2.1, 0.9, 0.6});
  EXPECT_FALSE(same_columns(cache.columns(map.resolution()), voxel_columns(map)));
  // The columns re-read are those of the blocks meeting the change (touching
  // counts): whole columns of blocks, 8 x 8 voxels (0.4 m), around it.
  const ColumnRect reread = cache.refresh(map, &changed);
  EXPECT_TRUE(same_columns(cache.columns(map.resolution()), voxel_columns(map)));
  EXPECT_EQ(reread.x0, 0);   // the block [0, 0.4] m touches x = 0.4
  EXPECT_EQ(reread.x1, 47);  // the block [2.0, 2.4] m holds x = 2.1
  EXPECT_EQ(reread.y0, 0);
  EXPECT_EQ(reread.y1, 23);
  // A change far from every block re-reads nothing.
  Bounds elsewhere;
  elsewhere.extend({50, 50, 50});
  EXPECT_TRUE(cache.refresh(map, &elsewhere).empty());
  // Blocks the map forgets are forgotten, wherever they are.
  map.blocks().clear();
  EXPECT_FALSE(cache.refresh(map, &elsewhere).empty());
  EXPECT_TRUE(cache.columns(map.resolution()).empty());
}

// The columns' extent follows the blocks' own: it grows with a far voxel
// and shrinks again when the only voxel at an edge is seen free.
TEST(OccupiedVoxelCache, ExtentGrowsAndShrinksWithTheEdgeBlocks) {
  metric::MetricMap map;  // 0.05 m voxels
  testing::set_voxel(map, {0.01, 0.01, 0.01}, true, ClassId::Terrain);
  testing::set_voxel(map, {0.21, 0.11, 0.01}, true, ClassId::Terrain);
  OccupiedVoxelCache cache;
  cache.refresh(map, nullptr);
  EXPECT_EQ(cache.columns(map.resolution()).width, 5);
  EXPECT_EQ(cache.columns(map.resolution()).height, 3);
  const Eigen::Vector3d far(3.01, -1.49, 0.51);
  testing::set_voxel(map, far, true, ClassId::Wall);
  Bounds changed;
  changed.extend(far);
  cache.refresh(map, &changed);
  VoxelColumns columns = cache.columns(map.resolution());
  EXPECT_TRUE(same_columns(columns, voxel_columns(map)));
  EXPECT_EQ(columns.x0, 0);
  EXPECT_EQ(columns.y0, -30);
  EXPECT_EQ(columns.width, 61);
  EXPECT_EQ(columns.height, 33);
  testing::set_voxel(map, far, false, ClassId::Unknown);
  cache.refresh(map, &changed);
  columns = cache.columns(map.resolution());
  EXPECT_TRUE(same_columns(columns, voxel_columns(map)));
  EXPECT_EQ(columns.width, 5);
  EXPECT_EQ(columns.height, 3);
}

}  // namespace
}  // namespace sarmap::topo
