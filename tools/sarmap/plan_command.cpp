// `sarmap plan RUNDIR --from x,y,z --to x,y,z [--graph tree|roadmap|grid]
// [--algorithm dijkstra|astar] [--out path.json]`: a path on the maps a run
// wrote (graph.json on segments.json and map.sarmap). No path is an answer
// (exit 0, found: false, with the reason), not an error.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/topo/graph_files.hpp"
#include "engine/topo/route_planner.hpp"
#include "tools/sarmap/commands.hpp"
#include "tools/sarmap/number_checks.hpp"
#include "tools/sarmap/run_route.hpp"

namespace sarmap::cli {
namespace {

struct PlanArgs {
  std::string run;
  std::string from, to;
  std::string graph = "tree";
  std::string algorithm = "dijkstra";
  std::string out;
  bool quiet = false;
};

Eigen::Vector3d parse_point(const std::string& text, const char* option) {
  const auto p = finite_number_list(text, 3);
  if (!p) {
    throw Error(ErrorCode::InvalidArgument,
                std::string("plan: ") + option + " must be x,y,z (three finite numbers), got '" + text + "'");
  }
  return {(*p)[0], (*p)[1], (*p)[2]};
}

void run_plan(const PlanArgs& a) {
  const auto graph = topo::route_graph_from(a.graph);
  if (!graph) throw Error(ErrorCode::InvalidArgument, "plan: --graph must be tree, roadmap or grid");
  const auto search = topo::route_search_from(a.algorithm);
  if (!search) throw Error(ErrorCode::InvalidArgument, "plan: --algorithm must be dijkstra or astar");
  const Eigen::Vector3d from = parse_point(a.from, "--from");
  const Eigen::Vector3d to = parse_point(a.to, "--to");
  const topo::Route route = plan_on_run(a.run, from, to, *graph, *search);
  if (!a.out.empty()) topo::write_route_json(a.out, route);
  if (a.quiet) return;
  if (!route.found) {
    std::printf("no path on the %s: %s\n", std::string(topo::to_string(route.graph)).c_str(), route.reason.c_str());
    return;
  }
  std::printf("path on the %s (%s): %.3f m, %zu points%s\n", std::string(topo::to_string(route.graph)).c_str(),
              route.graph == topo::RouteGraph::Grid ? "wavefront" : std::string(topo::to_string(route.search)).c_str(),
              route.length, route.points.size(),
              route.nodes.empty() ? "" : (", " + std::to_string(route.nodes.size()) + " nodes").c_str());
  for (const Eigen::Vector3d& p : route.points) std::printf("  %.3f %.3f %.3f\n", p.x(), p.y(), p.z());
}

}  // namespace

void add_plan_command(CLI::App& app) {
  auto args = std::make_shared<PlanArgs>();
  CLI::App* cmd = app.add_subcommand("plan", "Plan a path on the maps a run wrote");
  cmd->add_option("RUNDIR", args->run, "Folder written by `sarmap run`")->required();
  cmd->add_option("--from", args->from, "Start x,y,z (metres; taken down to the ground under it)")->required();
  cmd->add_option("--to", args->to, "Goal x,y,z")->required();
  cmd->add_option("--graph", args->graph, "tree (the spanning tree), roadmap (every passing edge) or grid (wavefront)")
      ->capture_default_str();
  cmd->add_option("--algorithm", args->algorithm, "dijkstra or astar (tree and roadmap)")->capture_default_str();
  cmd->add_option("--out", args->out, "Write the path as JSON here");
  cmd->add_flag("--quiet", args->quiet, "Print nothing (the path goes to --out)");
  cmd->callback([args] { run_plan(*args); });
}

}  // namespace sarmap::cli
