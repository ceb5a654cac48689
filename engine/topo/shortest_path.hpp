// Shortest paths on a CsrGraph (a spanning tree or the whole roadmap):
// Dijkstra and A* between two nodes, and Dijkstra from one node to all. Both
// searches share one binary heap and one set of per-node arrays that a
// PathSearch keeps between queries, so a query allocates only its answer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/topo/csr_graph.hpp"

namespace sarmap::topo {

struct GraphPath {
  bool found = false;
  std::vector<NodeId> nodes;  // source first, target last; {source} when they are equal
  std::vector<EdgeId> edges;  // nodes.size() - 1 input edge indices, edges[i] joins nodes[i] and nodes[i + 1]
  double cost =
      std::numeric_limits<double>::infinity();  // sum of the edges' weights; infinity when not found
  std::size_t expanded_nodes = 0;               // nodes taken off the heap, to compare A* with Dijkstra
};

// Searches one graph, which must outlive it. Not thread-safe: one per thread.
class PathSearch {
 public:
  explicit PathSearch(const CsrGraph& graph);

  // Throw sarmap::Error (InvalidArgument) for a node id out of range.
  GraphPath dijkstra(NodeId source, NodeId target);
  // Guided by the straight distance to the target, so needs the graph's
  // positions (InvalidArgument without them). Same cost as dijkstra(); the
  // path may differ when two paths cost the same.
  GraphPath a_star(NodeId source, NodeId target);
  // Cost from source to every node; infinity where unreachable.
  std::vector<double> distances_from(NodeId source);

 private:
  struct HeapEntry {
    double key;  // cost so far, plus the bound to the target for A*
    double cost;
    NodeId node;
  };

  static constexpr NodeId kNoTarget = std::numeric_limits<NodeId>::max();

  void run(NodeId source, NodeId target, bool guided);
  void start_query();
  bool reached(NodeId node) const { return stamp_[node] == generation_; }
  GraphPath path_to(NodeId source, NodeId target) const;
  void check_node(NodeId node, const char* role) const;

  const CsrGraph* graph_;
  // Per node, valid only where stamp_ equals the current query's generation,
  // so a query clears nothing it does not touch.
  std::vector<std::uint32_t> stamp_;
  std::vector<double> cost_;
  std::vector<NodeId> previous_node_;
  std::vector<EdgeId> previous_edge_;
  std::uint32_t generation_ = 0;
  std::vector<HeapEntry> heap_;
  std::size_t expanded_ = 0;
};

// One-off queries with a workspace of their own.
GraphPath dijkstra_path(const CsrGraph& graph, NodeId source, NodeId target);
GraphPath a_star_path(const CsrGraph& graph, NodeId source, NodeId target);
std::vector<double> dijkstra_distances(const CsrGraph& graph, NodeId source);

}  // namespace sarmap::topo
