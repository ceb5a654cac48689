// An undirected graph in compressed sparse row form (one array of neighbours,
// one offset per node) built once from an edge list, so path searches walk
// contiguous memory. Node positions ride along for A*'s straight-line bound.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "engine/topo/weighted_edge.hpp"

namespace sarmap::topo {

struct Neighbour {
  NodeId node;
  EdgeId edge;  // index into the edge list the graph was built from
  double weight;
};

class CsrGraph {
 public:
  CsrGraph() = default;
  // Keeps the edges the mask includes (empty mask: all), e.g. a spanning
  // forest's (mask_of_edges) or the whole roadmap's. Self-loops are left out:
  // no shortest path uses one. Each node's neighbours are listed in ascending
  // edge index, so searches over the graph are deterministic.
  // positions: empty, or one per node; when given, every kept edge's weight
  // must be at least the straight distance between its ends (what makes A*'s
  // heuristic admissible), checked here once rather than trusted.
  // Throws sarmap::Error (InvalidArgument) naming the bad edge or count.
  CsrGraph(std::size_t node_count, std::span<const WeightedEdge> edges, EdgeMask mask = {},
           std::vector<Eigen::Vector3d> positions = {});

  std::size_t node_count() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  // Undirected edges kept (each is stored once from either end).
  std::size_t edge_count() const { return neighbours_.size() / 2; }
  std::span<const Neighbour> neighbours(NodeId node) const {
    return {neighbours_.data() + offsets_[node], neighbours_.data() + offsets_[node + 1]};
  }

  bool has_positions() const { return !positions_.empty(); }
  const std::vector<Eigen::Vector3d>& positions() const { return positions_; }

 private:
  std::vector<std::size_t> offsets_;
  std::vector<Neighbour> neighbours_;
  std::vector<Eigen::Vector3d> positions_;
};

}  // namespace sarmap::topo
