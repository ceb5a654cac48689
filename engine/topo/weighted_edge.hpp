// The undirected weighted edge list every topo algorithm takes, and the one
// check of it (ids in range, weights finite and >= 0) they all share.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace sarmap::topo {

using NodeId = std::uint32_t;
// An index into the caller's edge list; results refer to edges by it, so the
// caller can map them back to whatever the edge stands for.
using EdgeId = std::uint32_t;

struct WeightedEdge {
  NodeId a = 0;
  NodeId b = 0;
  double weight = 0.0;
};

// Which edges an algorithm may use: empty means all, otherwise one byte per
// edge, nonzero = use it. Bytes rather than std::vector<bool> so callers can
// hand over a span of their own storage.
using EdgeMask = std::span<const std::uint8_t>;

// Throws sarmap::Error (InvalidArgument) naming the first bad edge: an end not
// below node_count, or a weight that is NaN, infinite or negative. Also
// rejects a mask whose size is neither 0 nor edges.size(), and counts that do
// not fit the 32-bit ids.
void check_edges(std::size_t node_count, std::span<const WeightedEdge> edges, EdgeMask mask = {});

inline bool is_included(EdgeMask mask, std::size_t edge) { return mask.empty() || mask[edge] != 0; }

// A mask with exactly the listed edges set (e.g. a spanning forest's edges).
std::vector<std::uint8_t> mask_of_edges(std::size_t edge_count, std::span<const EdgeId> chosen);

}  // namespace sarmap::topo
