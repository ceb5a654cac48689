#include "engine/topo/csr_graph.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "engine/core/error.hpp"

namespace sarmap::topo {
namespace {

void check_positions(std::size_t node_count, std::span<const WeightedEdge> edges, EdgeMask mask,
                     const std::vector<Eigen::Vector3d>& positions) {
  if (positions.empty()) return;
  if (positions.size() != node_count) {
    throw Error(ErrorCode::InvalidArgument, "topo: " + std::to_string(positions.size()) +
                                                " node positions for " + std::to_string(node_count) +
                                                " nodes");
  }
  for (std::size_t n = 0; n < positions.size(); ++n) {
    if (!positions[n].allFinite()) {
      throw Error(ErrorCode::InvalidArgument,
                  "topo: node " + std::to_string(n) + " has a non-finite position");
    }
  }
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (!is_included(mask, i)) continue;
    const WeightedEdge& e = edges[i];
    const double straight = (positions[e.a] - positions[e.b]).norm();
    // A relative slack of 1e-12 forgives a weight computed the same way in
    // another order; anything shorter would let A* return a longer path.
    if (e.weight < straight * (1.0 - 1e-12)) {
      throw Error(ErrorCode::InvalidArgument,
                  "topo: edge " + std::to_string(i) + " (" + std::to_string(e.a) + " - " +
                      std::to_string(e.b) + ") weighs " + std::to_string(e.weight) +
                      ", less than the straight distance " + std::to_string(straight) + " between its nodes");
    }
  }
}

}  // namespace

CsrGraph::CsrGraph(std::size_t node_count, std::span<const WeightedEdge> edges, EdgeMask mask,
                   std::vector<Eigen::Vector3d> positions)
    : positions_(std::move(positions)) {
  check_edges(node_count, edges, mask);
  check_positions(node_count, edges, mask, positions_);

  // Counting sort by node: degrees, prefix sums, then a fill in edge order.
  offsets_.assign(node_count + 1, 0);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (!is_included(mask, i) || edges[i].a == edges[i].b) continue;
    ++offsets_[edges[i].a + 1];
    ++offsets_[edges[i].b + 1];
  }
  for (std::size_t n = 0; n < node_count; ++n) offsets_[n + 1] += offsets_[n];
  neighbours_.resize(offsets_[node_count]);
  std::vector<std::size_t> next(offsets_.begin(), offsets_.end() - 1);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const WeightedEdge& e = edges[i];
    if (!is_included(mask, i) || e.a == e.b) continue;
    const auto id = static_cast<EdgeId>(i);
    neighbours_[next[e.a]++] = {e.b, id, e.weight};
    neighbours_[next[e.b]++] = {e.a, id, e.weight};
  }
}

}  // namespace sarmap::topo
