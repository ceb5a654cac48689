// The topo algorithms at the sizes the topological map and its planners meet:
// Kruskal's spanning forest over a random geometric graph of 10k nodes (edges
// to every node within a radius, about 11 neighbours each, as candidate edges
// between nodes would be; 100k to show the scaling and the parallel sort),
// one Dijkstra and one A* query on its tree and on the whole roadmap, and the
// wavefront planner across 500 x 500 and 1000 x 1000 grids with walls.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/topo/csr_graph.hpp"
#include "engine/topo/shortest_path.hpp"
#include "engine/topo/spanning_forest.hpp"
#include "engine/topo/wavefront_planner.hpp"

namespace {

using namespace sarmap::topo;

constexpr double kMeanNeighbours = 12.0;  // before the border trims it to about 11

struct Roadmap {
  std::vector<Eigen::Vector3d> positions;
  std::vector<WeightedEdge> edges;
};

// Nodes uniform in a square of side sqrt(n) metres (one node per square
// metre), joined to all others within the radius that gives kMeanNeighbours;
// pairs found through a bucket grid of radius-sized cells.
Roadmap random_geometric_graph(std::size_t node_count) {
  std::mt19937 random(42);
  const double side = std::sqrt(static_cast<double>(node_count));
  std::uniform_real_distribution<double> along(0.0, side);
  const double radius = std::sqrt(kMeanNeighbours / std::numbers::pi);
  Roadmap map;
  for (std::size_t i = 0; i < node_count; ++i) map.positions.emplace_back(along(random), along(random), 0.0);
  const auto cells = static_cast<std::int64_t>(std::ceil(side / radius));
  std::unordered_map<std::int64_t, std::vector<NodeId>> buckets;
  const auto bucket_of = [&](const Eigen::Vector3d& p) {
    return std::pair{static_cast<std::int64_t>(p.x() / radius), static_cast<std::int64_t>(p.y() / radius)};
  };
  for (NodeId i = 0; i < node_count; ++i) {
    const auto [bx, by] = bucket_of(map.positions[i]);
    buckets[by * cells + bx].push_back(i);
  }
  for (NodeId a = 0; a < node_count; ++a) {
    const auto [bx, by] = bucket_of(map.positions[a]);
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        if (bx + dx < 0 || by + dy < 0 || bx + dx >= cells || by + dy >= cells) continue;
        const auto found = buckets.find((by + dy) * cells + bx + dx);
        if (found == buckets.end()) continue;
        for (const NodeId b : found->second) {
          if (b <= a) continue;
          const double length = (map.positions[a] - map.positions[b]).norm();
          if (length <= radius) map.edges.push_back({a, b, length});
        }
      }
    }
  }
  return map;
}

const Roadmap& roadmap(std::size_t node_count) {
  static std::unordered_map<std::size_t, Roadmap> made;
  auto found = made.find(node_count);
  if (found == made.end()) found = made.emplace(node_count, random_geometric_graph(node_count)).first;
  return found->second;
}

void BM_SpanningForest(benchmark::State& state) {
  const Roadmap& map = roadmap(static_cast<std::size_t>(state.range(0)));
  SpanningForest forest;
  for (auto _ : state) {
    forest = minimum_spanning_forest(map.positions.size(), map.edges);
    benchmark::DoNotOptimize(forest.total_weight);
  }
  state.counters["edges"] = static_cast<double>(map.edges.size());
  state.counters["neighbours"] =
      2.0 * static_cast<double>(map.edges.size()) / static_cast<double>(map.positions.size());
  state.counters["trees"] = static_cast<double>(forest.tree_count);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(map.edges.size()));
}
BENCHMARK(BM_SpanningForest)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

// One query per iteration, cycling through 64 fixed random node pairs (so
// the figure is a mean over short and long paths); the PathSearch is reused,
// as a caller planning many paths would.
template <bool kAStar, bool kTree>
void BM_PathQuery(benchmark::State& state) {
  const Roadmap& map = roadmap(10000);
  std::vector<std::uint8_t> mask;
  if (kTree)
    mask = mask_of_edges(map.edges.size(), minimum_spanning_forest(map.positions.size(), map.edges).edges);
  const CsrGraph graph(map.positions.size(), map.edges, mask, map.positions);
  PathSearch search(graph);
  std::mt19937 random(7);
  std::vector<std::pair<NodeId, NodeId>> queries;
  queries.reserve(64);
  for (int i = 0; i < 64; ++i) {
    queries.emplace_back(static_cast<NodeId>(random() % map.positions.size()),
                         static_cast<NodeId>(random() % map.positions.size()));
  }
  std::size_t q = 0;
  double expanded = 0.0;
  double found = 0.0;
  for (auto _ : state) {
    const auto [s, t] = queries[q++ % queries.size()];
    const GraphPath path = kAStar ? search.a_star(s, t) : search.dijkstra(s, t);
    benchmark::DoNotOptimize(path.cost);
    expanded += static_cast<double>(path.expanded_nodes);
    found += path.found ? 1.0 : 0.0;
  }
  state.counters["expanded"] = benchmark::Counter(expanded, benchmark::Counter::kAvgIterations);
  state.counters["found"] = benchmark::Counter(found, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_PathQuery<false, true>)->Name("BM_Dijkstra/tree/10000")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PathQuery<true, true>)->Name("BM_AStar/tree/10000")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PathQuery<false, false>)->Name("BM_Dijkstra/roadmap/10000")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PathQuery<true, false>)->Name("BM_AStar/roadmap/10000")->Unit(benchmark::kMicrosecond);

// Free space with walls every 50 cells, each with a 10-cell gap at
// alternating ends, so the wave winds through the whole grid; 5 % of the
// cells are unknown (blocked, the default). Start and goal in opposite
// corners: the wave settles nearly every free cell.
PlanningGrid walled_grid(int side) {
  PlanningGrid grid(side, side, 0.05, Eigen::Vector2d::Zero(), CellState::Free);
  for (int x = 50; x < side; x += 50) {
    const bool gap_at_top = (x / 50) % 2 == 1;
    for (int y = 0; y < side; ++y) {
      const bool in_gap = gap_at_top ? y >= side - 10 : y < 10;
      if (!in_gap) grid.set({x, y}, CellState::Occupied);
    }
  }
  std::mt19937 random(3);
  for (CellState& c : grid.cells()) {
    if (c == CellState::Free && random() % 20 == 0) c = CellState::Unknown;
  }
  grid.set({1, 1}, CellState::Free);
  grid.set({side - 2, side - 2}, CellState::Free);
  return grid;
}

void BM_Wavefront(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  const PlanningGrid grid = walled_grid(side);
  WavefrontPlanner planner;
  GridPath path;
  for (auto _ : state) {
    path = planner.plan(grid, GridCell{1, 1}, GridCell{side - 2, side - 2});
    benchmark::DoNotOptimize(path.length_m);
  }
  if (!path.found()) state.SkipWithError("no path");
  state.counters["settled"] = static_cast<double>(path.settled_cells);
  state.counters["path_m"] = path.length_m;
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(path.settled_cells));
}
BENCHMARK(BM_Wavefront)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
