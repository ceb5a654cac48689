// Paths between two points of the map: on the topological map's tree or
// roadmap (Dijkstra or A*; each point attaches to the nearest node it reaches
// by a straight drive that passes), or on the traversability grid with the
// wavefront planner, an independent second answer. No path is an answer with
// a reason, not an error.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "engine/topo/topo_map.hpp"

namespace sarmap::topo {

enum class RouteGraph : std::uint8_t { Tree, Roadmap, Grid };
enum class RouteSearch : std::uint8_t { Dijkstra, AStar };

std::string_view to_string(RouteGraph graph);     // "tree", "roadmap", "grid"
std::string_view to_string(RouteSearch search);   // "dijkstra", "astar"
std::optional<RouteGraph> route_graph_from(std::string_view name);
std::optional<RouteSearch> route_search_from(std::string_view name);

struct Route {
  bool found = false;
  // When not found: "start_blocked" (the start stands in a wall, an obstacle
  // or a drop's rim, or reaches no node), "goal_blocked" (the same for the
  // goal), "unreachable" (no path joins them), "unknown_space" (the start or
  // goal is on ground never seen).
  std::string reason;
  RouteGraph graph = RouteGraph::Tree;
  RouteSearch search = RouteSearch::Dijkstra;  // the grid always uses the wavefront
  double length = 0;                            // metres, along the points
  std::vector<Eigen::Vector3d> points;          // start and goal on the ground, nodes or cells between
  std::vector<std::uint32_t> nodes;             // graph routes only
};

// Start and goal are taken to the ground under them (their z is replaced).
// Throws sarmap::Error (InvalidArgument) for non-finite points.
Route plan_route(const TopoMap& map, const Eigen::Vector3d& from, const Eigen::Vector3d& to, RouteGraph graph,
                 RouteSearch search = RouteSearch::Dijkstra);

}  // namespace sarmap::topo
