// Scores a run's topological map (graph.json) against the arena: how many of
// its edges cross a true wall or box (the exact segment-against-box test at
// the robot's body heights, independent of the Embree scene the map was built
// with), and for each of the arena's eval_pairs the route on the tree, the
// roadmap and the grid against the shortest drivable path on a fine
// ground-truth grid of the arena, for the same robot (radius, step).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "engine/eval/truth_paths.hpp"
#include "engine/sim/arena.hpp"
#include "engine/topo/graph_files.hpp"
#include "engine/topo/route_planner.hpp"

namespace sarmap::eval {

struct RouteScore {
  bool found = false;
  std::string reason;            // when not found
  double length = 0;             // metres
  std::optional<double> ratio;   // length over the true path's, when both are found
};

struct PairScore {
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  TruthPath truth;  // its any_angle_length is the length routes are held to
  RouteScore tree, roadmap, grid;
};

struct GraphScores {
  std::size_t nodes = 0, edges = 0, tree_edges = 0;
  std::size_t edges_crossing = 0, tree_edges_crossing = 0;  // edges that cross a true wall or box
  std::vector<std::pair<std::uint32_t, std::uint32_t>> crossing;  // their node ids
  // Empty when the run lacks what routes need (segments.json, map.sarmap).
  std::vector<PairScore> pairs;
};

// `routes`: the map restored from the run, or null to score the edges only.
GraphScores score_graph(const sim::Arena& arena, const topo::GraphFile& graph, const topo::TopoMap* routes);

void add_graph_scores_json(const GraphScores& scores, nlohmann::ordered_json& out);
std::string format_graph_scores(const GraphScores& scores);
// One line for the demo's summary.
std::string graph_scores_summary(const GraphScores& scores);

}  // namespace sarmap::eval
