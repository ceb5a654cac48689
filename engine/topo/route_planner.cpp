#include "engine/topo/route_planner.hpp"

#include <algorithm>
#include <cmath>

#include "engine/core/error.hpp"
#include "engine/topo/csr_graph.hpp"
#include "engine/topo/shortest_path.hpp"
#include "engine/topo/wavefront_planner.hpp"

namespace sarmap::topo {
namespace {

// How many of the nearest nodes a start or goal tries to drive to.
constexpr std::size_t kAttachTries = 32;

// Where a point stands: on the grid's surface, or why it cannot.
struct Stand {
  Eigen::Vector3d position;
  std::string problem;  // "" or "blocked" or "unknown_space"
};

Stand stand_at(const TopoMap& map, const Eigen::Vector3d& p) {
  const TraversabilityGrid& t = map.grid();
  const GridCell cell = t.grid.cell_at(p.head<2>());
  if (!t.grid.contains(cell)) return {p, "unknown_space"};
  const float g = t.ground_at(cell);
  if (t.grid.at(cell) == CellState::Occupied) return {p, "blocked"};
  if (std::isnan(g)) return {p, "unknown_space"};
  return {{p.x(), p.y(), g}, ""};
}

// The nearest alive node reachable by a passing straight drive, or none.
std::optional<std::uint32_t> attach(const TopoMap& map, const Eigen::Vector3d& stand, bool towards) {
  std::vector<std::pair<double, std::uint32_t>> nearest;
  for (const TopoNode& node : map.nodes()) {
    if (node.alive) nearest.emplace_back((node.position - stand).norm(), node.id);
  }
  const std::size_t tries = std::min(kAttachTries, nearest.size());
  std::partial_sort(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(tries), nearest.end());
  for (std::size_t k = 0; k < tries; ++k) {
    const Eigen::Vector3d& node = map.nodes()[nearest[k].second].position;
    const GroundProfile drive = towards ? map.check_drive(stand, node) : map.check_drive(node, stand);
    if (drive.verdict == DriveVerdict::Passes) return nearest[k].second;
  }
  return std::nullopt;
}

double polyline_length(const std::vector<Eigen::Vector3d>& points) {
  double length = 0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

Route not_found(Route route, std::string reason) {
  route.found = false;
  route.reason = std::move(reason);
  return route;
}

Route plan_on_graph(const TopoMap& map, const Stand& start, const Stand& goal, Route route) {
  const std::optional<std::uint32_t> first = attach(map, start.position, true);
  if (!first) return not_found(route, "start_blocked");
  const std::optional<std::uint32_t> last = attach(map, goal.position, false);
  if (!last) return not_found(route, "goal_blocked");
  std::vector<WeightedEdge> edges(map.edges().size());
  std::vector<std::uint8_t> mask(edges.size(), 1);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const TopoEdge& e = map.edges()[i];
    edges[i] = {e.a, e.b, e.length};
    if (route.graph == RouteGraph::Tree) mask[i] = e.in_tree;
  }
  std::vector<Eigen::Vector3d> positions(map.nodes().size());
  for (const TopoNode& node : map.nodes()) positions[node.id] = node.position;
  const CsrGraph graph(map.nodes().size(), edges, mask, std::move(positions));
  PathSearch search(graph);
  const GraphPath path = route.search == RouteSearch::AStar ? search.a_star(*first, *last) : search.dijkstra(*first, *last);
  if (!path.found) return not_found(route, "unreachable");
  route.found = true;
  route.nodes = path.nodes;
  route.points.push_back(start.position);
  for (NodeId n : path.nodes) route.points.push_back(map.nodes()[n].position);
  route.points.push_back(goal.position);
  route.length = polyline_length(route.points);
  return route;
}

Route plan_on_grid(const TopoMap& map, const Stand& start, const Stand& goal, Route route) {
  const TraversabilityGrid& t = map.grid();
  WavefrontSettings settings;
  settings.unknown_cells = map.settings().unknown_traversable ? UnknownCells::Free : UnknownCells::Blocked;
  const GridPath path = plan_wavefront(t.grid, t.grid.cell_at(start.position.head<2>()),
                                       t.grid.cell_at(goal.position.head<2>()), settings);
  switch (path.status) {
    case GridPlanStatus::Found: break;
    case GridPlanStatus::StartOutside:
    case GridPlanStatus::GoalOutside: return not_found(route, "unknown_space");
    case GridPlanStatus::StartBlocked: return not_found(route, "start_blocked");
    case GridPlanStatus::GoalBlocked: return not_found(route, "goal_blocked");
    case GridPlanStatus::Unreachable: return not_found(route, "unreachable");
  }
  route.found = true;
  route.points.push_back(start.position);
  double z = start.position.z();
  for (std::size_t i = 1; i + 1 < path.cells.size(); ++i) {
    // Unknown cells (when allowed) keep the last seen height.
    const float g = t.ground_at(path.cells[i]);
    if (!std::isnan(g)) z = g;
    route.points.emplace_back(path.points[i].x(), path.points[i].y(), z);
  }
  route.points.push_back(goal.position);
  route.length = polyline_length(route.points);
  return route;
}

}  // namespace

std::string_view to_string(RouteGraph graph) {
  switch (graph) {
    case RouteGraph::Tree: return "tree";
    case RouteGraph::Roadmap: return "roadmap";
    case RouteGraph::Grid: return "grid";
  }
  return "?";
}

std::string_view to_string(RouteSearch search) { return search == RouteSearch::AStar ? "astar" : "dijkstra"; }

std::optional<RouteGraph> route_graph_from(std::string_view name) {
  for (RouteGraph g : {RouteGraph::Tree, RouteGraph::Roadmap, RouteGraph::Grid}) {
    if (to_string(g) == name) return g;
  }
  return std::nullopt;
}

std::optional<RouteSearch> route_search_from(std::string_view name) {
  for (RouteSearch s : {RouteSearch::Dijkstra, RouteSearch::AStar}) {
    if (to_string(s) == name) return s;
  }
  return std::nullopt;
}

Route plan_route(const TopoMap& map, const Eigen::Vector3d& from, const Eigen::Vector3d& to, RouteGraph graph,
                 RouteSearch search) {
  if (!from.allFinite() || !to.allFinite()) {
    throw Error(ErrorCode::InvalidArgument, "plan: the start and the goal must be finite points");
  }
  Route route;
  route.graph = graph;
  route.search = search;
  const Stand start = stand_at(map, from);
  const Stand goal = stand_at(map, to);
  if (start.problem == "unknown_space" || goal.problem == "unknown_space") return not_found(route, "unknown_space");
  if (!start.problem.empty()) return not_found(route, "start_blocked");
  if (!goal.problem.empty()) return not_found(route, "goal_blocked");
  return graph == RouteGraph::Grid ? plan_on_grid(map, start, goal, route) : plan_on_graph(map, start, goal, route);
}

}  // namespace sarmap::topo
