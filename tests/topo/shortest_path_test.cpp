// Dijkstra and A* on random geometric graphs (the roadmap and its spanning
// forest): equal costs, equal to a Bellman-Ford written the plain way, and
// paths that are walks of the graph they searched; unreachable targets,
// deterministic ties, workspace reuse, and the errors.
#include "engine/topo/shortest_path.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "tests/io/error_message.hpp"
#include "engine/topo/spanning_forest.hpp"

namespace sarmap::topo {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct GeometricGraph {
  std::vector<Eigen::Vector3d> positions;
  std::vector<WeightedEdge> edges;
};

// Nodes in a box, edges between those within radius, each weighing its
// straight length times 1 to 1.5 (a detour, as an edge over a ramp might).
// A small radius leaves several components.
GeometricGraph geometric_graph(std::mt19937& random, std::size_t node_count, double radius) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  GeometricGraph g;
  for (std::size_t i = 0; i < node_count; ++i)
    g.positions.emplace_back(unit(random), unit(random), 0.2 * unit(random));
  for (NodeId a = 0; a < node_count; ++a) {
    for (NodeId b = a + 1; b < node_count; ++b) {
      const double length = (g.positions[a] - g.positions[b]).norm();
      if (length <= radius) g.edges.push_back({a, b, length * (1.0 + 0.5 * unit(random))});
    }
  }
  return g;
}

std::vector<double> bellman_ford(std::size_t node_count, const std::vector<WeightedEdge>& edges,
                                 const std::vector<std::uint8_t>& mask, NodeId source) {
  std::vector<double> distance(node_count, kInfinity);
  distance[source] = 0.0;
  for (std::size_t round = 0; round < node_count; ++round) {
    bool changed = false;
    for (std::size_t i = 0; i < edges.size(); ++i) {
      if (!mask.empty() && !mask[i]) continue;
      const WeightedEdge& e = edges[i];
      for (const auto& [from, to] : {std::pair{e.a, e.b}, std::pair{e.b, e.a}}) {
        if (distance[from] + e.weight < distance[to]) {
          distance[to] = distance[from] + e.weight;
          changed = true;
        }
      }
    }
    if (!changed) break;
  }
  return distance;
}

// The path starts and ends where asked, and each step follows an edge the
// mask includes between the two nodes it joins; the weights add up to the cost.
void expect_walk(const GraphPath& path, const std::vector<WeightedEdge>& edges,
                 const std::vector<std::uint8_t>& mask, NodeId source, NodeId target) {
  ASSERT_TRUE(path.found);
  ASSERT_FALSE(path.nodes.empty());
  EXPECT_EQ(path.nodes.front(), source);
  EXPECT_EQ(path.nodes.back(), target);
  ASSERT_EQ(path.edges.size() + 1, path.nodes.size());
  double cost = 0.0;
  for (std::size_t i = 0; i < path.edges.size(); ++i) {
    const EdgeId e = path.edges[i];
    ASSERT_LT(e, edges.size());
    EXPECT_TRUE(mask.empty() || mask[e]) << "edge " << e << " is not in the searched graph";
    const bool joins = (edges[e].a == path.nodes[i] && edges[e].b == path.nodes[i + 1]) ||
                       (edges[e].b == path.nodes[i] && edges[e].a == path.nodes[i + 1]);
    EXPECT_TRUE(joins) << "edge " << e << " does not join " << path.nodes[i] << " and " << path.nodes[i + 1];
    cost += edges[e].weight;
  }
  EXPECT_NEAR(cost, path.cost, 1e-12 * std::max(1.0, cost));
}

TEST(ShortestPath, DijkstraAndAStarAgreeOnRoadmapsAndTrees) {
  std::mt19937 random(3);
  std::size_t astar_expanded = 0;
  std::size_t dijkstra_expanded = 0;
  int unreachable = 0;
  int found = 0;
  for (int round = 0; round < 40; ++round) {
    SCOPED_TRACE("graph " + std::to_string(round));
    const std::size_t n = 20 + random() % 100;
    const GeometricGraph g = geometric_graph(random, n, round % 3 == 0 ? 0.12 : 0.25);
    const SpanningForest forest = minimum_spanning_forest(n, g.edges);
    const std::vector<std::uint8_t> tree_mask = mask_of_edges(g.edges.size(), forest.edges);
    for (const std::vector<std::uint8_t>& mask : {std::vector<std::uint8_t>{}, tree_mask}) {
      const CsrGraph graph(n, g.edges, mask, g.positions);
      EXPECT_EQ(graph.edge_count(), mask.empty() ? g.edges.size() : forest.edges.size());
      PathSearch search(graph);
      for (int q = 0; q < 5; ++q) {
        const auto source = static_cast<NodeId>(random() % n);
        const auto target = static_cast<NodeId>(random() % n);
        const std::vector<double> reference = bellman_ford(n, g.edges, mask, source);
        const GraphPath by_dijkstra = search.dijkstra(source, target);
        const GraphPath by_astar = search.a_star(source, target);
        EXPECT_EQ(search.distances_from(source), dijkstra_distances(graph, source));
        ASSERT_EQ(by_dijkstra.found, reference[target] < kInfinity);
        ASSERT_EQ(by_astar.found, by_dijkstra.found);
        if (!by_dijkstra.found) {
          ++unreachable;
          EXPECT_EQ(by_dijkstra.cost, kInfinity);
          EXPECT_TRUE(by_dijkstra.nodes.empty() && by_astar.nodes.empty());
          EXPECT_EQ(search.distances_from(source)[target], kInfinity);
          continue;
        }
        ++found;
        EXPECT_NEAR(by_dijkstra.cost, reference[target], 1e-12);
        EXPECT_NEAR(by_astar.cost, by_dijkstra.cost, 1e-12);
        expect_walk(by_dijkstra, g.edges, mask, source, target);
        expect_walk(by_astar, g.edges, mask, source, target);
        // A tree has one path between two nodes.
        if (!mask.empty()) {
          EXPECT_EQ(by_astar.nodes, by_dijkstra.nodes);
        }
        astar_expanded += by_astar.expanded_nodes;
        dijkstra_expanded += by_dijkstra.expanded_nodes;
      }
    }
  }
  EXPECT_GT(found, 200);
  EXPECT_GT(unreachable, 10);
  // The straight-line bound only prunes: A* never settles more than Dijkstra overall.
  EXPECT_LT(astar_expanded, dijkstra_expanded);
}

TEST(ShortestPath, EqualCostPathsAreBrokenTowardTheLowerNodeId) {
  // A square: 0-1-3 and 0-2-3 cost the same; the search settles 1 before 2.
  const std::vector<WeightedEdge> edges{{0, 2, 1.0}, {2, 3, 1.0}, {0, 1, 1.0}, {1, 3, 1.0}};
  const CsrGraph graph(4, edges);
  const GraphPath path = dijkstra_path(graph, 0, 3);
  EXPECT_EQ(path.nodes, (std::vector<NodeId>{0, 1, 3}));
  EXPECT_EQ(path.edges, (std::vector<EdgeId>{2, 3}));
  EXPECT_EQ(path.cost, 2.0);
}

TEST(ShortestPath, ParallelEdgesUseTheLighterAndSelfLoopsAreLeftOut) {
  const std::vector<WeightedEdge> edges{{0, 1, 3.0}, {1, 1, 0.0}, {1, 0, 2.0}, {1, 2, 1.0}};
  const CsrGraph graph(3, edges);
  EXPECT_EQ(graph.edge_count(), 3u);
  EXPECT_EQ(graph.neighbours(1).size(), 3u);
  const GraphPath path = dijkstra_path(graph, 0, 2);
  EXPECT_EQ(path.edges, (std::vector<EdgeId>{2, 3}));
  EXPECT_EQ(path.cost, 3.0);
}

TEST(ShortestPath, NeighboursAreListedInEdgeOrder) {
  const std::vector<WeightedEdge> edges{{2, 0, 1.0}, {0, 1, 1.0}, {3, 0, 1.0}, {1, 2, 1.0}};
  const std::vector<std::uint8_t> mask{1, 0, 1, 1};
  const CsrGraph graph(4, edges, mask);
  const auto around_0 = graph.neighbours(0);
  ASSERT_EQ(around_0.size(), 2u);
  EXPECT_EQ(around_0[0].node, 2u);
  EXPECT_EQ(around_0[0].edge, 0u);
  EXPECT_EQ(around_0[1].node, 3u);
  EXPECT_EQ(around_0[1].edge, 2u);
  EXPECT_EQ(graph.neighbours(1).size(), 1u);
}

TEST(ShortestPath, SourceEqualToTargetIsAPathOfOneNode) {
  const std::vector<WeightedEdge> edges{{0, 1, 1.0}};
  const CsrGraph graph(2, edges, {}, {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()});
  for (const GraphPath& path : {dijkstra_path(graph, 1, 1), a_star_path(graph, 1, 1)}) {
    EXPECT_TRUE(path.found);
    EXPECT_EQ(path.nodes, (std::vector<NodeId>{1}));
    EXPECT_TRUE(path.edges.empty());
    EXPECT_EQ(path.cost, 0.0);
  }
}

TEST(ShortestPath, UnreachableTargetsAndIsolatedNodes) {
  // Two components {0, 1} and {2, 3}; node 4 has no edge.
  const std::vector<WeightedEdge> edges{{0, 1, 1.0}, {2, 3, 1.0}};
  const CsrGraph graph(5, edges);
  const GraphPath path = dijkstra_path(graph, 0, 3);
  EXPECT_FALSE(path.found);
  EXPECT_EQ(path.cost, kInfinity);
  EXPECT_TRUE(path.nodes.empty());
  EXPECT_TRUE(path.edges.empty());
  EXPECT_FALSE(dijkstra_path(graph, 4, 0).found);
  EXPECT_EQ(dijkstra_distances(graph, 0), (std::vector<double>{0.0, 1.0, kInfinity, kInfinity, kInfinity}));
}

TEST(ShortestPath, ReusedSearchAnswersAsAFreshOne) {
  std::mt19937 random(9);
  const GeometricGraph g = geometric_graph(random, 150, 0.2);
  const CsrGraph graph(150, g.edges, {}, g.positions);
  PathSearch reused(graph);
  for (int q = 0; q < 100; ++q) {
    const auto s = static_cast<NodeId>(random() % 150);
    const auto t = static_cast<NodeId>(random() % 150);
    const GraphPath again = q % 2 ? reused.a_star(s, t) : reused.dijkstra(s, t);
    const GraphPath fresh = q % 2 ? a_star_path(graph, s, t) : dijkstra_path(graph, s, t);
    EXPECT_EQ(again.nodes, fresh.nodes);
    EXPECT_EQ(again.edges, fresh.edges);
    EXPECT_EQ(again.cost, fresh.cost);
    EXPECT_EQ(again.expanded_nodes, fresh.expanded_nodes);
  }
}

TEST(ShortestPath, BadQueriesAndGraphsAreRefused) {
  const std::vector<WeightedEdge> edges{{0, 1, 1.0}};
  const CsrGraph without_positions(2, edges);
  test::expect_invalid_argument([&] { dijkstra_path(without_positions, 2, 0); },
                 "the source node 2 is out of range (2 nodes)");
  test::expect_invalid_argument([&] { dijkstra_path(without_positions, 0, 7); }, "the target node 7 is out of range");
  test::expect_invalid_argument([&] { dijkstra_distances(without_positions, 9); }, "the source node 9");
  test::expect_invalid_argument([&] { a_star_path(without_positions, 0, 1); }, "A* needs node positions");
  test::expect_invalid_argument([&] { CsrGraph(2, edges, {}, {Eigen::Vector3d::Zero()}); }, "1 node positions for 2 nodes");
  test::expect_invalid_argument(
      [&] {
        CsrGraph(2, edges, {}, {Eigen::Vector3d::Zero(), Eigen::Vector3d(std::nan(""), 0, 0)});
      },
      "node 1 has a non-finite position");
  // Shorter than the straight line would make A*'s bound overestimate.
  test::expect_invalid_argument(
      [&] {
        CsrGraph(2, edges, {}, {Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 0, 0)});
      },
      "edge 0 (0 - 1) weighs 1.000000, less than the straight distance 2.000000");
  // ... unless the mask leaves that edge out.
  const std::vector<std::uint8_t> none{0};
  EXPECT_NO_THROW(CsrGraph(2, edges, none, {Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 0, 0)}));
  test::expect_invalid_argument([&] { CsrGraph(1, edges); },
                 "edge 0 (0 - 1, weight 1): node id 1 is out of range (1 nodes)");
}

}  // namespace
}  // namespace sarmap::topo
