#include "engine/topo/weighted_edge.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::topo {
namespace {

std::string describe(std::size_t index, const WeightedEdge& e) {
  std::ostringstream out;
  out << "edge " << index << " (" << e.a << " - " << e.b << ", weight " << e.weight << ")";
  return out.str();
}

}  // namespace

void check_edges(std::size_t node_count, std::span<const WeightedEdge> edges, EdgeMask mask) {
  constexpr std::size_t kMaxIds = std::numeric_limits<std::uint32_t>::max();
  if (node_count > kMaxIds) {
    throw Error(ErrorCode::InvalidArgument,
                "topo: " + std::to_string(node_count) + " nodes do not fit 32-bit node ids");
  }
  if (edges.size() > kMaxIds) {
    throw Error(ErrorCode::InvalidArgument,
                "topo: " + std::to_string(edges.size()) + " edges do not fit 32-bit edge ids");
  }
  if (!mask.empty() && mask.size() != edges.size()) {
    throw Error(ErrorCode::InvalidArgument, "topo: the edge mask has " + std::to_string(mask.size()) +
                                                " entries for " + std::to_string(edges.size()) + " edges");
  }
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const WeightedEdge& e = edges[i];
    if (e.a >= node_count || e.b >= node_count) {
      throw Error(ErrorCode::InvalidArgument,
                  "topo: " + describe(i, e) + ": node id " + std::to_string(e.a >= node_count ? e.a : e.b) +
                      " is out of range (" + std::to_string(node_count) + " nodes)");
    }
    if (!std::isfinite(e.weight) || e.weight < 0.0) {
      throw Error(ErrorCode::InvalidArgument,
                  "topo: " + describe(i, e) + ": the weight must be a finite number >= 0");
    }
  }
}

std::vector<std::uint8_t> mask_of_edges(std::size_t edge_count, std::span<const EdgeId> chosen) {
  std::vector<std::uint8_t> mask(edge_count, 0);
  for (const EdgeId e : chosen) {
    if (e >= edge_count) {
      throw Error(ErrorCode::InvalidArgument, "topo: edge id " + std::to_string(e) + " is out of range (" +
                                                  std::to_string(edge_count) + " edges)");
    }
    mask[e] = 1;
  }
  return mask;
}

}  // namespace sarmap::topo
