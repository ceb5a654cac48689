// The topological map on simulated arenas, built by the pipeline from
// ground-truth labels: no edge of the tree or the roadmap crosses a true wall
// (exact geometry, not Embree) in the default, building and random arenas;
// ramp feet and tops stand off the slope; routes reach what they should and
// report why they cannot reach the rest; the maps do not depend on the
// thread count.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "engine/eval/truth_paths.hpp"
#include "engine/pipeline/mapper.hpp"
#include "engine/segments/segment_files.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/random_arena.hpp"
#include "engine/sim/simulator.hpp"
#include "engine/topo/graph_files.hpp"
#include "engine/topo/route_planner.hpp"
#include "tests/release_only.hpp"

namespace sarmap {
namespace {

std::unique_ptr<pipeline::Mapper> map_arena(const sim::Arena& arena, std::size_t frame_stride) {
  pipeline::MapperConfig config;
  config.classifier.kind = pipeline::ClassifierKind::Labels;
  auto mapper = std::make_unique<pipeline::Mapper>(config, sim::sensor_info(arena.sensor));
  const sim::Simulator simulator(arena);
  for (std::size_t f = 0; f < simulator.frame_count(); f += frame_stride) {
    Scan scan = simulator.simulate(f);
    mapper->integrate(scan);
  }
  return mapper;
}

sim::Arena shipped_arena(const char* name) {
  return sim::load_arena(std::string(SARMAP_SOURCE_DIR) + "/datasets/arenas/" + name);
}

// Every roadmap edge (the tree's are among them) at every body height, against the true walls and boxes.
void expect_no_edge_crosses_a_wall(const sim::Arena& arena, const topo::TopoMap& topo) {
  std::vector<geometry::Segment> drives;
  for (const topo::TopoEdge& e : topo.edges()) {
    for (double h : topo.settings().body_heights) {
      const Eigen::Vector3d lift(0, 0, h);
      drives.push_back({topo.nodes()[e.a].position + lift, topo.nodes()[e.b].position + lift});
    }
  }
  const std::vector<bool> crossing = eval::segments_crossing_walls(arena, drives);
  std::size_t crossings = 0;
  for (std::size_t i = 0; i < crossing.size(); ++i) {
    if (!crossing[i]) continue;
    ++crossings;
    ADD_FAILURE() << arena.name << ": edge " << i / topo.settings().body_heights.size() << " from "
                  << drives[i].p.transpose() << " to " << drives[i].q.transpose() << " crosses a wall";
  }
  EXPECT_EQ(crossings, 0u);
  EXPECT_FALSE(topo.edges().empty()) << arena.name;
}

// Foot and top nodes stand off every inclined ramp's footprint.
void expect_ramp_nodes_off_the_slope(const sim::Arena& arena, const topo::TopoMap& topo) {
  for (const topo::TopoNode& n : topo.nodes()) {
    if (!n.alive || (n.kind != topo::NodeKind::RampFoot && n.kind != topo::NodeKind::RampTop)) continue;
    for (const sim::ArenaElement& element : arena.elements) {
      const auto* ramp = std::get_if<sim::InclinedRampSpec>(&element.shape);
      if (ramp == nullptr) continue;
      const double yaw = ramp->yaw_deg * std::numbers::pi / 180;
      const Eigen::Vector2d d = n.position.head<2>() - ramp->center;
      const double along = d.x() * std::cos(yaw) + d.y() * std::sin(yaw);
      const double across = -d.x() * std::sin(yaw) + d.y() * std::cos(yaw);
      const bool on_slope = std::abs(along) < ramp->length / 2 - 0.01 && std::abs(across) < ramp->width / 2 - 0.01;
      EXPECT_FALSE(on_slope) << arena.name << ": node " << n.id << " at " << n.position.transpose();
    }
  }
}

TEST(TopoArena, DefaultArena) {
  RELEASE_ONLY();  // figures of the whole default arena; RampLeadsOntoAPlatform runs under the sanitizers
  const sim::Arena arena = shipped_arena("esogu-6x4.json");
  const auto mapper = map_arena(arena, 1);
  const topo::TopoMap& topo = mapper->topo_map();
  expect_no_edge_crosses_a_wall(arena, topo);
  expect_ramp_nodes_off_the_slope(arena, topo);
  std::size_t feet = 0;
  for (const topo::TopoNode& n : topo.nodes()) {
    if (!n.alive || n.kind != topo::NodeKind::RampFoot) continue;
    ++feet;
    EXPECT_LT(n.position.z(), 0.06);  // on the floor
  }
  EXPECT_EQ(feet, 2u);  // both ramps; neither leads anywhere, so no tops
  // The arena's pairs: the floor pair is reachable on every graph, the
  // platform (no ramp leads onto it) on none.
  for (topo::RouteGraph g : {topo::RouteGraph::Tree, topo::RouteGraph::Roadmap, topo::RouteGraph::Grid}) {
    const topo::Route floor = topo::plan_route(topo, arena.eval_pairs[1].first, arena.eval_pairs[1].second, g);
    EXPECT_TRUE(floor.found) << topo::to_string(g) << ": " << floor.reason;
    const topo::Route platform = topo::plan_route(topo, arena.eval_pairs[0].first, arena.eval_pairs[0].second, g);
    EXPECT_FALSE(platform.found) << topo::to_string(g);
    EXPECT_EQ(platform.reason, "unreachable") << topo::to_string(g);
  }
}

TEST(TopoArena, RampLeadsOntoAPlatform) {
  const sim::Arena arena = sim::load_arena(std::string(SARMAP_SOURCE_DIR) + "/tests/pipeline/data/ramp_to_platform.json");
  const auto mapper = map_arena(arena, 1);
  const topo::TopoMap& topo = mapper->topo_map();
  expect_no_edge_crosses_a_wall(arena, topo);
  expect_ramp_nodes_off_the_slope(arena, topo);
  const topo::TopoNode* foot = nullptr;
  const topo::TopoNode* top = nullptr;
  for (const topo::TopoNode& n : topo.nodes()) {
    if (n.alive && n.kind == topo::NodeKind::RampFoot) foot = &n;
    if (n.alive && n.kind == topo::NodeKind::RampTop) top = &n;
  }
  ASSERT_NE(foot, nullptr);
  ASSERT_NE(top, nullptr);
  EXPECT_LT(foot->position.x(), 1.4);  // below the low edge at x = 1.4
  EXPECT_NEAR(foot->position.z(), 0.0, 0.06);
  EXPECT_GT(top->position.x(), 2.6);  // past the high edge at x = 2.6, on the platform
  EXPECT_NEAR(top->position.z(), 0.3, 0.06);
  // Up the ramp: the route's nodes include the foot and the top.
  for (topo::RouteGraph g : {topo::RouteGraph::Tree, topo::RouteGraph::Roadmap, topo::RouteGraph::Grid}) {
    const topo::Route r = topo::plan_route(topo, arena.eval_pairs[0].first, arena.eval_pairs[0].second, g);
    ASSERT_TRUE(r.found) << topo::to_string(g) << ": " << r.reason;
    EXPECT_NEAR(r.points.back().z(), 0.3, 0.06);
    if (g == topo::RouteGraph::Grid) continue;
    EXPECT_NE(std::find(r.nodes.begin(), r.nodes.end(), foot->id), r.nodes.end());
    EXPECT_NE(std::find(r.nodes.begin(), r.nodes.end(), top->id), r.nodes.end());
  }
  // Off the platform's other sides there is no way down: every edge between
  // floor and platform runs up the ramp (its middle over the ramp's footprint,
  // x 1.4 to 2.6, y 1.0 to 2.0).
  std::size_t climbs = 0;
  for (const topo::TopoEdge& e : topo.edges()) {
    const Eigen::Vector3d& a = topo.nodes()[e.a].position;
    const Eigen::Vector3d& b = topo.nodes()[e.b].position;
    if (std::abs(a.z() - b.z()) < 0.15) continue;
    ++climbs;
    const Eigen::Vector3d mid = (a + b) / 2;
    EXPECT_TRUE(mid.x() > 1.4 && mid.x() < 2.6 && mid.y() > 1.0 && mid.y() < 2.0) << e.a << "-" << e.b;
  }
  EXPECT_GE(climbs, 1u);
}

TEST(TopoArena, SameMapsOnOneAndTwoThreads) {
  const sim::Arena arena = sim::load_arena(std::string(SARMAP_SOURCE_DIR) + "/tests/pipeline/data/ramp_to_platform.json");
  auto build = [&arena](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const auto mapper = map_arena(arena, 2);
    return std::make_pair(segments::segments_json(mapper->segment_map()), topo::graph_json(mapper->topo_map()));
  };
  const auto one = build(1), two = build(2);
  EXPECT_EQ(one.first, two.first);
  EXPECT_EQ(one.second, two.second);
}

TEST(TopoArena, BuildingArena) {
  RELEASE_ONLY();
  const sim::Arena arena = shipped_arena("building-52x15.json");
  const auto mapper = map_arena(arena, 2);
  const topo::TopoMap& topo = mapper->topo_map();
  expect_no_edge_crosses_a_wall(arena, topo);
  expect_ramp_nodes_off_the_slope(arena, topo);
  // Down the corridor from one end of the building to the other. (The arena's
  // own pair starts and ends where the robot stood at its first and last
  // frame, ground its camera never saw: unknown space.)
  for (topo::RouteGraph g : {topo::RouteGraph::Tree, topo::RouteGraph::Roadmap, topo::RouteGraph::Grid}) {
    const topo::Route r = topo::plan_route(topo, {2.5, 7.5, 0}, {49.5, 7.5, 0}, g);
    EXPECT_TRUE(r.found) << topo::to_string(g) << ": " << r.reason;
    EXPECT_GT(r.length, 47.0);
  }
  EXPECT_EQ(topo::plan_route(topo, arena.eval_pairs[0].first, arena.eval_pairs[0].second, topo::RouteGraph::Grid).reason,
            "unknown_space");
}

TEST(TopoArena, RandomArenas) {
  RELEASE_ONLY();
  for (std::uint64_t seed : {11, 12}) {
    const sim::Arena arena = sim::random_arena(seed);
    const auto mapper = map_arena(arena, 3);
    expect_no_edge_crosses_a_wall(arena, mapper->topo_map());
    expect_ramp_nodes_off_the_slope(arena, mapper->topo_map());
  }
}

}  // namespace
}  // namespace sarmap
