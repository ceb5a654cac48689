#include "engine/eval/graph_scores.hpp"

#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

namespace sarmap::eval {
namespace {

using Json = nlohmann::ordered_json;

RouteScore score_route(const topo::TopoMap& map, const PairScore& pair, topo::RouteGraph graph) {
  const topo::Route route = topo::plan_route(map, pair.from, pair.to, graph);
  RouteScore score;
  score.found = route.found;
  score.reason = route.reason;
  score.length = route.length;
  if (route.found && pair.truth.found && pair.truth.any_angle_length > 0) {
    score.ratio = route.length / pair.truth.any_angle_length;
  }
  return score;
}

Json route_json(const RouteScore& r) {
  Json j;
  j["found"] = r.found;
  if (!r.found) j["reason"] = r.reason;
  j["length"] = r.length;
  j["ratio_to_truth"] = r.ratio ? Json(*r.ratio) : Json(nullptr);
  return j;
}

std::string route_text(const RouteScore& r) {
  char text[64];
  if (!r.found) return r.reason;
  if (r.ratio) {
    std::snprintf(text, sizeof text, "%.2f m (%.2fx)", r.length, *r.ratio);
  } else {
    std::snprintf(text, sizeof text, "%.2f m", r.length);
  }
  return text;
}

std::string truth_text(const TruthPath& t) {
  if (!t.found) return std::string(path_status_name(t.status));
  char text[32];
  std::snprintf(text, sizeof text, "%.2f m", t.any_angle_length);
  return text;
}

}  // namespace

GraphScores score_graph(const sim::Arena& arena, const topo::GraphFile& graph, const topo::TopoMap* routes) {
  GraphScores s;
  for (const topo::TopoNode& n : graph.nodes) s.nodes += n.alive;
  s.edges = graph.edges.size();
  std::vector<geometry::Segment> drives;
  const std::size_t heights = graph.settings.body_heights.size();
  for (const topo::TopoEdge& e : graph.edges) {
    s.tree_edges += e.in_tree;
    for (double h : graph.settings.body_heights) {
      const Eigen::Vector3d lift(0, 0, h);
      drives.push_back({graph.nodes[e.a].position + lift, graph.nodes[e.b].position + lift});
    }
  }
  const std::vector<bool> crossing = segments_crossing_walls(arena, drives);
  for (std::size_t e = 0; e < graph.edges.size(); ++e) {
    bool crosses = false;
    for (std::size_t h = 0; h < heights; ++h) crosses = crosses || crossing[e * heights + h];
    if (!crosses) continue;
    ++s.edges_crossing;
    s.tree_edges_crossing += graph.edges[e].in_tree;
    s.crossing.emplace_back(graph.edges[e].a, graph.edges[e].b);
  }
  if (routes == nullptr) return s;
  // The truth drives the same robot: its radius and the step it climbs.
  DrivableSettings truth_settings;
  truth_settings.robot_radius = graph.settings.robot_radius;
  truth_settings.max_step = graph.settings.max_step;
  const DrivableGrid truth_grid(arena, truth_settings);
  for (const auto& [from, to] : arena.eval_pairs) {
    PairScore p;
    p.from = from;
    p.to = to;
    p.truth = shortest_path(truth_grid, from, to);
    p.tree = score_route(*routes, p, topo::RouteGraph::Tree);
    p.roadmap = score_route(*routes, p, topo::RouteGraph::Roadmap);
    p.grid = score_route(*routes, p, topo::RouteGraph::Grid);
    s.pairs.push_back(std::move(p));
  }
  return s;
}

void add_graph_scores_json(const GraphScores& s, Json& out) {
  Json g;
  g["nodes"] = s.nodes;
  g["edges"] = s.edges;
  g["tree_edges"] = s.tree_edges;
  g["edges_crossing_walls"] = s.edges_crossing;
  g["tree_edges_crossing_walls"] = s.tree_edges_crossing;
  g["crossing"] = Json::array();
  for (const auto& [a, b] : s.crossing) g["crossing"].push_back(Json::array({a, b}));
  g["pairs"] = Json::array();
  for (const PairScore& p : s.pairs) {
    Json pj;
    pj["from"] = Json::array({p.from.x(), p.from.y(), p.from.z()});
    pj["to"] = Json::array({p.to.x(), p.to.y(), p.to.z()});
    pj["truth"] = {{"found", p.truth.found},
                   {"status", path_status_name(p.truth.status)},
                   {"length", p.truth.any_angle_length},
                   {"grid_length", p.truth.length}};
    pj["tree"] = route_json(p.tree);
    pj["roadmap"] = route_json(p.roadmap);
    pj["grid"] = route_json(p.grid);
    g["pairs"].push_back(pj);
  }
  out["graph"] = g;
}

std::string format_graph_scores(const GraphScores& s) {
  std::ostringstream out;
  out << "topological map: " << s.nodes << " nodes, " << s.edges << " roadmap edges (" << s.tree_edges
      << " in the tree)\n";
  out << "  edges crossing a true wall or box: " << s.edges_crossing << " (tree: " << s.tree_edges_crossing << ")\n";
  for (std::size_t i = 0; i < s.pairs.size(); ++i) {
    const PairScore& p = s.pairs[i];
    char head[160];
    std::snprintf(head, sizeof head, "  pair %zu (%.2f, %.2f, %.2f) -> (%.2f, %.2f, %.2f)\n", i + 1, p.from.x(),
                  p.from.y(), p.from.z(), p.to.x(), p.to.y(), p.to.z());
    out << head;
    out << "    truth    " << truth_text(p.truth) << "\n";
    out << "    tree     " << route_text(p.tree) << "\n";
    out << "    roadmap  " << route_text(p.roadmap) << "\n";
    out << "    grid     " << route_text(p.grid) << "\n";
  }
  return out.str();
}

std::string graph_scores_summary(const GraphScores& s) {
  std::ostringstream out;
  out << s.nodes << " nodes, " << s.edges << " edges (" << s.tree_edges << " in the tree), " << s.edges_crossing
      << " crossing a true wall";
  for (std::size_t i = 0; i < s.pairs.size(); ++i) {
    const PairScore& p = s.pairs[i];
    out << "; pair " << i + 1 << ": truth " << truth_text(p.truth) << ", tree " << route_text(p.tree)
        << ", roadmap " << route_text(p.roadmap) << ", grid " << route_text(p.grid);
  }
  return out.str();
}

}  // namespace sarmap::eval
