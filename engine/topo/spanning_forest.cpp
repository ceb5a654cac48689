#include "engine/topo/spanning_forest.hpp"

#include <algorithm>
#include <cstdint>
#include <tuple>

#include <tbb/parallel_sort.h>

#include "engine/topo/union_find.hpp"

namespace sarmap::topo {
namespace {

// The sort key copied out of the edge so the sort reads contiguous memory
// instead of chasing an index per comparison.
struct SortKey {
  double weight;
  NodeId low;
  NodeId high;
  EdgeId edge;

  friend bool operator<(const SortKey& x, const SortKey& y) {
    return std::tie(x.weight, x.low, x.high, x.edge) < std::tie(y.weight, y.low, y.high, y.edge);
  }
};

SortKey key_of(std::span<const WeightedEdge> edges, EdgeId index) {
  const WeightedEdge& e = edges[index];
  return {e.weight, std::min(e.a, e.b), std::max(e.a, e.b), index};
}

}  // namespace

bool precedes_in_kruskal_order(std::span<const WeightedEdge> edges, EdgeId x, EdgeId y) {
  return key_of(edges, x) < key_of(edges, y);
}

SpanningForest minimum_spanning_forest(std::size_t node_count, std::span<const WeightedEdge> edges,
                                       EdgeMask mask) {
  check_edges(node_count, edges, mask);

  std::vector<SortKey> order;
  order.reserve(edges.size());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    // Self-loops can never be taken; leaving them out keeps the sort shorter.
    if (is_included(mask, i) && edges[i].a != edges[i].b)
      order.push_back(key_of(edges, static_cast<EdgeId>(i)));
  }
  // The order is total, so a parallel sort gives the same forest. On 2 cores
  // it took 2.8 ms for 59k edges where std::sort took 4.4 (0.32 and 0.33 ms
  // for 5.8k); below 500 elements oneTBB sorts serially anyway.
  tbb::parallel_sort(order.begin(), order.end());

  SpanningForest forest;
  UnionFind trees(node_count);
  const std::size_t most_edges = node_count == 0 ? 0 : node_count - 1;
  forest.edges.reserve(std::min(most_edges, order.size()));
  for (const SortKey& key : order) {
    if (forest.edges.size() == most_edges) break;  // already one tree: nothing more can join
    if (!trees.unite(key.low, key.high)) continue;
    forest.edges.push_back(key.edge);
    forest.total_weight += key.weight;
  }
  forest.tree_count = node_count - forest.edges.size();
  return forest;
}

}  // namespace sarmap::topo
