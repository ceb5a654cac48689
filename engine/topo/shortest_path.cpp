#include "engine/topo/shortest_path.hpp"

#include <algorithm>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::topo {
namespace {

// std::push_heap builds a max-heap, so "less" here means "comes out later":
// the smallest key first, ties to the smaller node id, which makes the search
// order (and so the path among equal-cost ones) independent of anything but the graph.
struct ComesOutLater {
  template <typename Entry>
  bool operator()(const Entry& x, const Entry& y) const {
    if (x.key != y.key) return x.key > y.key;
    return x.node > y.node;
  }
};

}  // namespace

PathSearch::PathSearch(const CsrGraph& graph)
    : graph_(&graph),
      stamp_(graph.node_count(), 0),
      cost_(graph.node_count()),
      previous_node_(graph.node_count()),
      previous_edge_(graph.node_count()) {}

void PathSearch::check_node(NodeId node, const char* role) const {
  if (node >= graph_->node_count()) {
    throw Error(ErrorCode::InvalidArgument, std::string("topo: the ") + role + " node " +
                                                std::to_string(node) + " is out of range (" +
                                                std::to_string(graph_->node_count()) + " nodes)");
  }
}

void PathSearch::start_query() {
  if (++generation_ == 0) {
    // After 2^32 queries the stamps would alias old ones: clear them once.
    std::fill(stamp_.begin(), stamp_.end(), 0);
    generation_ = 1;
  }
  heap_.clear();
  expanded_ = 0;
}

void PathSearch::run(NodeId source, NodeId target, bool guided) {
  start_query();
  const std::vector<Eigen::Vector3d>& positions = graph_->positions();
  const auto bound = [&](NodeId node) { return guided ? (positions[node] - positions[target]).norm() : 0.0; };

  stamp_[source] = generation_;
  cost_[source] = 0.0;
  previous_node_[source] = source;
  previous_edge_[source] = 0;
  heap_.push_back({bound(source), 0.0, source});
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), ComesOutLater{});
    const HeapEntry top = heap_.back();
    heap_.pop_back();
    // Entries are pushed only on a strict improvement, so an entry whose cost
    // is above the node's current one is outdated (lazy deletion).
    if (top.cost > cost_[top.node]) continue;
    ++expanded_;
    if (top.node == target) return;
    for (const Neighbour& n : graph_->neighbours(top.node)) {
      const double cost = top.cost + n.weight;
      if (reached(n.node) && cost >= cost_[n.node]) continue;
      stamp_[n.node] = generation_;
      cost_[n.node] = cost;
      previous_node_[n.node] = top.node;
      previous_edge_[n.node] = n.edge;
      heap_.push_back({cost + bound(n.node), cost, n.node});
      std::push_heap(heap_.begin(), heap_.end(), ComesOutLater{});
    }
  }
}

GraphPath PathSearch::path_to(NodeId source, NodeId target) const {
  GraphPath path;
  path.expanded_nodes = expanded_;
  if (!reached(target)) return path;
  path.found = true;
  path.cost = cost_[target];
  for (NodeId node = target; node != source; node = previous_node_[node]) {
    path.nodes.push_back(node);
    path.edges.push_back(previous_edge_[node]);
  }
  path.nodes.push_back(source);
  std::reverse(path.nodes.begin(), path.nodes.end());
  std::reverse(path.edges.begin(), path.edges.end());
  return path;
}

GraphPath PathSearch::dijkstra(NodeId source, NodeId target) {
  check_node(source, "source");
  check_node(target, "target");
  run(source, target, false);
  return path_to(source, target);
}

GraphPath PathSearch::a_star(NodeId source, NodeId target) {
  check_node(source, "source");
  check_node(target, "target");
  if (!graph_->has_positions()) {
    throw Error(ErrorCode::InvalidArgument, "topo: A* needs node positions and the graph has none");
  }
  run(source, target, true);
  return path_to(source, target);
}

std::vector<double> PathSearch::distances_from(NodeId source) {
  check_node(source, "source");
  run(source, kNoTarget, false);
  std::vector<double> distances(graph_->node_count(), std::numeric_limits<double>::infinity());
  for (std::size_t n = 0; n < distances.size(); ++n) {
    if (reached(static_cast<NodeId>(n))) distances[n] = cost_[n];
  }
  return distances;
}

GraphPath dijkstra_path(const CsrGraph& graph, NodeId source, NodeId target) {
  return PathSearch(graph).dijkstra(source, target);
}

GraphPath a_star_path(const CsrGraph& graph, NodeId source, NodeId target) {
  return PathSearch(graph).a_star(source, target);
}

std::vector<double> dijkstra_distances(const CsrGraph& graph, NodeId source) {
  return PathSearch(graph).distances_from(source);
}

}  // namespace sarmap::topo
