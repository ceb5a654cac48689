// Minimum spanning forest by Kruskal's algorithm: one pass over the edges in a
// fixed total order, a union-find deciding which join two trees. Over the
// edges that pass a wall test this equals the thesis's repeat-until-no-collision
// tree with its colliding edges dropped, edge for edge (tests/topo shows it).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "engine/topo/weighted_edge.hpp"

namespace sarmap::topo {

struct SpanningForest {
  // Indices into the input edges, in the order Kruskal took them (ascending
  // by the tie rule below).
  std::vector<EdgeId> edges;
  double total_weight = 0.0;
  // Trees in the forest, isolated nodes included: node_count - edges.size().
  std::size_t tree_count = 0;
};

// Edges are taken in ascending (weight, min(a, b), max(a, b), edge index)
// order, a total order, so the forest is unique whatever the input order or
// the sort used. A self-loop never joins two trees and is never taken; of
// parallel edges at most one (the first in that order) is. Only edges the
// mask includes are considered (empty mask: all). Throws sarmap::Error as
// check_edges does.
SpanningForest minimum_spanning_forest(std::size_t node_count, std::span<const WeightedEdge> edges,
                                       EdgeMask mask = {});

// The comparison behind that order, for callers and tests that need to sort
// edges the same way.
bool precedes_in_kruskal_order(std::span<const WeightedEdge> edges, EdgeId x, EdgeId y);

}  // namespace sarmap::topo
