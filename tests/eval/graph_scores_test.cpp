// Graph figures: edges against the true walls (a hand-made graph), and the
// whole scoring on a simulated room with a doorway mapped by the pipeline.
#include "engine/eval/graph_scores.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "engine/pipeline/mapper.hpp"
#include "engine/sim/simulator.hpp"

namespace sarmap::eval {
namespace {

sim::Arena room_with_door() {
  return sim::load_arena(std::string(SARMAP_SOURCE_DIR) + "/tests/cli/data/room_with_door.json");
}

topo::TopoNode node(std::uint32_t id, double x, double y) {
  topo::TopoNode n;
  n.id = id;
  n.position = {x, y, 0};
  return n;
}

TEST(GraphScores, EdgesThroughAWallAreCountedAndThroughTheDoorNot) {
  topo::GraphFile graph;
  graph.nodes = {node(0, 1.0, 0.5), node(1, 3.0, 0.5), node(2, 1.0, 1.5), node(3, 3.0, 1.5)};
  auto edge = [&](std::uint32_t a, std::uint32_t b, bool tree) {
    topo::TopoEdge e;
    e.a = a;
    e.b = b;
    e.length = (graph.nodes[a].position - graph.nodes[b].position).norm();
    e.in_tree = tree;
    return e;
  };
  graph.edges = {edge(0, 1, true), edge(2, 3, true), edge(0, 2, false)};  // through the wall, the door, beside it
  const GraphScores s = score_graph(room_with_door(), graph, nullptr);
  EXPECT_EQ(s.nodes, 4u);
  EXPECT_EQ(s.tree_edges, 2u);
  EXPECT_EQ(s.edges_crossing, 1u);
  EXPECT_EQ(s.tree_edges_crossing, 1u);
  ASSERT_EQ(s.crossing.size(), 1u);
  EXPECT_EQ(s.crossing[0], std::make_pair(0u, 1u));
  EXPECT_TRUE(s.pairs.empty());  // no map to plan on
}

TEST(GraphScores, ThePipelinesMapOfARoomWithADoor) {
  const sim::Arena arena = room_with_door();
  pipeline::MapperConfig config;
  config.classifier.kind = pipeline::ClassifierKind::Labels;
  pipeline::Mapper mapper(config, sim::sensor_info(arena.sensor));
  const sim::Simulator simulator(arena);
  for (std::size_t f = 0; f < simulator.frame_count(); ++f) {
    Scan scan = simulator.simulate(f);
    mapper.integrate(scan);
  }
  const topo::TopoMap& topo = mapper.topo_map();
  topo::GraphFile graph;
  graph.settings = topo.settings();
  graph.nodes = topo.nodes();
  graph.edges = topo.edges();
  const GraphScores s = score_graph(arena, graph, &topo);
  EXPECT_EQ(s.edges_crossing, 0u);
  ASSERT_EQ(s.pairs.size(), 1u);
  const PairScore& p = s.pairs[0];
  ASSERT_TRUE(p.truth.found);
  // The straight line happens to pass through the doorway's middle.
  EXPECT_NEAR(p.truth.any_angle_length, std::hypot(2.8, 1.8), 0.05);
  for (const RouteScore* r : {&p.tree, &p.roadmap, &p.grid}) {
    ASSERT_TRUE(r->found) << r->reason;
    ASSERT_TRUE(r->ratio.has_value());
    // Never shorter than the true shortest path (up to the truth's cell size), and not absurdly longer.
    EXPECT_GT(*r->ratio, 0.97);
    EXPECT_LT(*r->ratio, 2.0);
  }
  EXPECT_LE(p.roadmap.length, p.tree.length + 1e-9);
  nlohmann::ordered_json j;
  add_graph_scores_json(s, j);
  EXPECT_EQ(j["graph"]["edges_crossing_walls"], 0);
  EXPECT_TRUE(j["graph"]["pairs"][0]["roadmap"]["found"].get<bool>());
  EXPECT_NE(format_graph_scores(s).find("roadmap"), std::string::npos);
}

}  // namespace
}  // namespace sarmap::eval
