// Kruskal's spanning forest against two others: a direct implementation of
// the thesis's loop (MST over all candidate edges by Prim's algorithm,
// colliding tree edges made huge and the MST recomputed until none is left
// but those the graph cannot do without, which are then dropped), edge for
// edge; and Boost Graph Library's kruskal_minimum_spanning_tree over the
// passing edges, in total weight. On random graphs with ties, parallel edges,
// self-loops and disconnected parts; then the tie rule and the errors by hand.
#include "engine/topo/spanning_forest.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iterator>
#include <limits>
#include <queue>
#include <random>
#include <tuple>
#include <vector>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/kruskal_min_spanning_tree.hpp>

#include "engine/core/error.hpp"
#include "tests/io/error_message.hpp"
#include "engine/topo/union_find.hpp"

namespace sarmap::topo {
namespace {

struct RandomGraph {
  std::size_t node_count = 0;
  std::vector<WeightedEdge> edges;
  std::vector<std::uint8_t> collides;  // 1 where the edge crosses a wall
};

// Small integer weights in some graphs make ties common; parallel edges and
// self-loops come from drawing ends independently.
RandomGraph random_graph(std::mt19937& random, std::size_t max_nodes) {
  RandomGraph g;
  g.node_count = 1 + random() % max_nodes;
  const std::size_t edge_count = random() % (3 * g.node_count + 1);
  const bool integer_weights = random() % 2 == 0;
  const double collision_rate = std::array{0.0, 0.2, 0.5, 0.9}[random() % 4];
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = 0; i < edge_count; ++i) {
    WeightedEdge e;
    e.a = static_cast<NodeId>(random() % g.node_count);
    e.b = random() % 10 == 0 ? e.a : static_cast<NodeId>(random() % g.node_count);
    e.weight = integer_weights ? static_cast<double>(random() % 4) : 10.0 * unit(random);
    g.edges.push_back(e);
    g.collides.push_back(unit(random) < collision_rate ? 1 : 0);
  }
  return g;
}

std::vector<std::uint8_t> passing_mask(const RandomGraph& g) {
  std::vector<std::uint8_t> mask(g.collides.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = g.collides[i] ? 0 : 1;
  return mask;
}

// Prim's algorithm from each not yet reached node in id order, ordering edges
// by (weight, min end, max end, index) over the given weights: with that
// total order the minimum spanning forest is unique, so any correct algorithm
// must return the same edges.
std::vector<EdgeId> prim_forest(std::size_t node_count, const std::vector<WeightedEdge>& edges,
                                const std::vector<double>& weights) {
  std::vector<std::vector<EdgeId>> incident(node_count);
  for (EdgeId i = 0; i < edges.size(); ++i) {
    incident[edges[i].a].push_back(i);
    incident[edges[i].b].push_back(i);
  }
  using Key = std::tuple<double, NodeId, NodeId, EdgeId>;
  const auto key = [&](EdgeId i) {
    return Key{weights[i], std::min(edges[i].a, edges[i].b), std::max(edges[i].a, edges[i].b), i};
  };
  std::vector<bool> in_tree(node_count, false);
  std::vector<EdgeId> tree;
  for (NodeId root = 0; root < node_count; ++root) {
    if (in_tree[root]) continue;
    std::priority_queue<Key, std::vector<Key>, std::greater<>> frontier;
    const auto add = [&](NodeId node) {
      in_tree[node] = true;
      for (const EdgeId i : incident[node]) frontier.push(key(i));
    };
    add(root);
    while (!frontier.empty()) {
      const EdgeId i = std::get<3>(frontier.top());
      frontier.pop();
      const NodeId outside = !in_tree[edges[i].a] ? edges[i].a : edges[i].b;
      if (in_tree[outside]) continue;
      tree.push_back(i);
      add(outside);
    }
  }
  return tree;
}

struct ThesisTree {
  std::vector<EdgeId> edges;  // the passing tree edges, in Kruskal's order
  int rounds = 0;             // MSTs computed
};

ThesisTree thesis_loop(const RandomGraph& g) {
  // Above any real weight: colliding edges go last but stay usable.
  constexpr double kHuge = 1e12;
  std::vector<double> weights(g.edges.size());
  for (std::size_t i = 0; i < weights.size(); ++i) weights[i] = g.edges[i].weight;
  ThesisTree result;
  std::vector<EdgeId> tree;
  while (true) {
    tree = prim_forest(g.node_count, g.edges, weights);
    ++result.rounds;
    bool changed = false;
    for (const EdgeId i : tree) {
      if (g.collides[i] && weights[i] != kHuge) {
        weights[i] = kHuge;
        changed = true;
      }
    }
    if (!changed) break;
  }
  for (const EdgeId i : tree) {
    if (!g.collides[i]) result.edges.push_back(i);
  }
  std::sort(result.edges.begin(), result.edges.end(),
            [&](EdgeId x, EdgeId y) { return precedes_in_kruskal_order(g.edges, x, y); });
  return result;
}

double boost_forest_weight(const RandomGraph& g, std::size_t& edge_count) {
  using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, boost::no_property,
                                      boost::property<boost::edge_weight_t, double>>;
  Graph graph(g.node_count);
  for (std::size_t i = 0; i < g.edges.size(); ++i) {
    if (!g.collides[i]) boost::add_edge(g.edges[i].a, g.edges[i].b, g.edges[i].weight, graph);
  }
  std::vector<boost::graph_traits<Graph>::edge_descriptor> tree;
  boost::kruskal_minimum_spanning_tree(graph, std::back_inserter(tree));
  const auto weight = boost::get(boost::edge_weight, graph);
  double total = 0.0;
  for (const auto& e : tree) total += weight[e];
  edge_count = tree.size();
  return total;
}

std::size_t component_count(const RandomGraph& g, const std::vector<std::uint8_t>& mask) {
  UnionFind sets(g.node_count);
  for (std::size_t i = 0; i < g.edges.size(); ++i) {
    if (mask[i]) sets.unite(g.edges[i].a, g.edges[i].b);
  }
  return sets.set_count();
}

TEST(SpanningForest, EqualsTheThesisLoopEdgeForEdgeAndBoostInWeight) {
  std::mt19937 random(2021);
  int graphs_needing_several_rounds = 0;
  int disconnected_graphs = 0;
  for (int round = 0; round < 400; ++round) {
    SCOPED_TRACE("graph " + std::to_string(round));
    const RandomGraph g = random_graph(random, round < 300 ? 40 : 300);
    const std::vector<std::uint8_t> mask = passing_mask(g);
    const SpanningForest forest = minimum_spanning_forest(g.node_count, g.edges, mask);

    const ThesisTree thesis = thesis_loop(g);
    ASSERT_EQ(forest.edges, thesis.edges);
    double thesis_weight = 0.0;
    for (const EdgeId i : thesis.edges) thesis_weight += g.edges[i].weight;
    EXPECT_EQ(forest.total_weight, thesis_weight);  // same edges summed in the same order

    std::size_t boost_edges = 0;
    const double boost_weight = boost_forest_weight(g, boost_edges);
    EXPECT_EQ(forest.edges.size(), boost_edges);
    EXPECT_NEAR(forest.total_weight, boost_weight, 1e-9 * std::max(1.0, boost_weight));

    const std::size_t components = component_count(g, mask);
    EXPECT_EQ(forest.tree_count, components);
    EXPECT_EQ(forest.edges.size(), g.node_count - components);
    for (const EdgeId i : forest.edges) {
      EXPECT_TRUE(mask[i]);
      EXPECT_NE(g.edges[i].a, g.edges[i].b);
    }
    graphs_needing_several_rounds += thesis.rounds > 1;
    disconnected_graphs += components > 1;
  }
  // The comparison means something only if the loop had to iterate and
  // forests (not just trees) came up.
  EXPECT_GT(graphs_needing_several_rounds, 100);
  EXPECT_GT(disconnected_graphs, 100);
}

TEST(SpanningForest, LargeEdgeListsSortedInParallelGiveTheSameForest) {
  // Enough edges for the parallel sort, with ties everywhere (weights 0..9).
  std::mt19937 random(5);
  RandomGraph g;
  g.node_count = 20000;
  for (int i = 0; i < 150000; ++i) {
    g.edges.push_back({static_cast<NodeId>(random() % g.node_count),
                       static_cast<NodeId>(random() % g.node_count), static_cast<double>(random() % 10)});
  }
  g.collides.assign(g.edges.size(), 0);
  const SpanningForest forest = minimum_spanning_forest(g.node_count, g.edges);
  std::vector<double> weights(g.edges.size());
  for (std::size_t i = 0; i < weights.size(); ++i) weights[i] = g.edges[i].weight;
  std::vector<EdgeId> reference = prim_forest(g.node_count, g.edges, weights);
  std::sort(reference.begin(), reference.end(),
            [&](EdgeId x, EdgeId y) { return precedes_in_kruskal_order(g.edges, x, y); });
  EXPECT_EQ(forest.edges, reference);
}

TEST(SpanningForest, TiesGoToTheLowerNodeIdsThenTheLowerEdgeIndex) {
  // A triangle of equal weights: (0,1) and (0,2) win over (1,2), whichever
  // way round the ends are written.
  const std::vector<WeightedEdge> triangle{{2, 1, 1.0}, {2, 0, 1.0}, {1, 0, 1.0}};
  EXPECT_EQ(minimum_spanning_forest(3, triangle).edges, (std::vector<EdgeId>{2, 1}));
  // Parallel edges of one weight: the first listed is taken.
  const std::vector<WeightedEdge> parallel{{1, 0, 2.0}, {0, 1, 2.0}, {0, 1, 3.0}};
  const SpanningForest forest = minimum_spanning_forest(2, parallel);
  EXPECT_EQ(forest.edges, (std::vector<EdgeId>{0}));
  EXPECT_EQ(forest.total_weight, 2.0);
  // A lighter parallel edge wins whatever its index.
  const std::vector<WeightedEdge> lighter_later{{0, 1, 2.0}, {1, 0, 0.5}};
  EXPECT_EQ(minimum_spanning_forest(2, lighter_later).edges, (std::vector<EdgeId>{1}));
}

TEST(SpanningForest, SelfLoopsAreNeverTaken) {
  const std::vector<WeightedEdge> edges{{0, 0, 0.0}, {1, 1, 0.0}, {0, 1, 5.0}, {2, 2, 0.0}};
  const SpanningForest forest = minimum_spanning_forest(3, edges);
  EXPECT_EQ(forest.edges, (std::vector<EdgeId>{2}));
  EXPECT_EQ(forest.total_weight, 5.0);
  EXPECT_EQ(forest.tree_count, 2u);  // {0, 1} and the lone node 2
}

TEST(SpanningForest, ResultDoesNotDependOnTheInputOrder) {
  std::mt19937 random(11);
  const RandomGraph g = random_graph(random, 50);
  const auto chosen = [](const std::vector<WeightedEdge>& edges, const SpanningForest& forest) {
    std::vector<std::tuple<double, NodeId, NodeId>> picked;
    for (const EdgeId i : forest.edges) {
      picked.emplace_back(edges[i].weight, std::min(edges[i].a, edges[i].b),
                          std::max(edges[i].a, edges[i].b));
    }
    return picked;
  };
  const auto expected = chosen(g.edges, minimum_spanning_forest(g.node_count, g.edges));
  std::vector<WeightedEdge> shuffled = g.edges;
  for (int k = 0; k < 5; ++k) {
    std::shuffle(shuffled.begin(), shuffled.end(), random);
    for (WeightedEdge& e : shuffled) {
      if (random() % 2) std::swap(e.a, e.b);
    }
    EXPECT_EQ(chosen(shuffled, minimum_spanning_forest(g.node_count, shuffled)), expected);
  }
}

TEST(SpanningForest, EmptyGraphsAndLoneNodes) {
  EXPECT_TRUE(minimum_spanning_forest(0, {}).edges.empty());
  const SpanningForest lone = minimum_spanning_forest(3, {});
  EXPECT_TRUE(lone.edges.empty());
  EXPECT_EQ(lone.tree_count, 3u);
  EXPECT_EQ(lone.total_weight, 0.0);
  // Every edge masked out.
  const std::vector<WeightedEdge> edges{{0, 1, 1.0}};
  const std::vector<std::uint8_t> none{0};
  EXPECT_TRUE(minimum_spanning_forest(2, edges, none).edges.empty());
}

TEST(SpanningForest, BadEdgesAreRefusedByIndex) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  test::expect_invalid_argument(
      [&] {
        minimum_spanning_forest(3, std::vector<WeightedEdge>{{0, 1, 1.0}, {1, 2, nan}});
      },
      "edge 1 (1 - 2, weight nan)");
  test::expect_invalid_argument(
      [&] {
        minimum_spanning_forest(3, std::vector<WeightedEdge>{{0, 1, -0.5}});
      },
      "edge 0 (0 - 1, weight -0.5): the weight must be a finite number >= 0");
  test::expect_invalid_argument([&] { minimum_spanning_forest(3, std::vector<WeightedEdge>{{0, 1, inf}}); }, "edge 0");
  test::expect_invalid_argument(
      [&] {
        minimum_spanning_forest(3, std::vector<WeightedEdge>{{0, 1, 1.0}, {0, 2, 1.0}, {3, 0, 1.0}});
      },
      "edge 2 (3 - 0, weight 1): node id 3 is out of range (3 nodes)");
  const std::vector<std::uint8_t> short_mask{1};
  test::expect_invalid_argument(
      [&] {
        minimum_spanning_forest(3, std::vector<WeightedEdge>{{0, 1, 1.0}, {1, 2, 1.0}}, short_mask);
      },
      "the edge mask has 1 entries for 2 edges");
  // Masked-out edges are checked too: a bad value is a caller's bug wherever it sits.
  const std::vector<std::uint8_t> skip_second{1, 0};
  test::expect_invalid_argument(
      [&] {
        minimum_spanning_forest(3, std::vector<WeightedEdge>{{0, 1, 1.0}, {1, 2, nan}}, skip_second);
      },
      "edge 1");
}

TEST(SpanningForest, MaskOfEdgesMarksTheChosenOnes) {
  const std::vector<EdgeId> chosen{3, 0};
  EXPECT_EQ(mask_of_edges(5, chosen), (std::vector<std::uint8_t>{1, 0, 0, 1, 0}));
  const std::vector<EdgeId> beyond{5};
  test::expect_invalid_argument([&] { mask_of_edges(5, beyond); }, "edge id 5 is out of range (5 edges)");
}

}  // namespace
}  // namespace sarmap::topo
