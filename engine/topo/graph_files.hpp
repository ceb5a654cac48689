// The topological map's files, written atomically:
// - graph.json, networkx's node-link form (networkx.node_link_graph loads it):
//   {"directed": false, "multigraph": false, "graph": {the settings},
//    "nodes": [{"id", "pos": [x, y, z], "kind", "segment"}],
//    "links": [{"source", "target", "length", "slope_deg", "ground", "in_tree"}]}
//   Retired nodes are left out; ids keep their gaps.
// - graph.graphml: the same for GraphML readers (position as x, y, z: GraphML has no lists).
// - graph.ply: nodes as points coloured by the class they stand on, edges as
//   lines (tree edges black, the rest of the roadmap grey), for MeshLab or Open3D.
// And a planned route as path.json: {"found", "reason" (when not found),
// "graph", "algorithm", "length", "points": [[x, y, z], ...], "nodes": [ids] (graph routes)}.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "engine/topo/route_planner.hpp"
#include "engine/topo/topo_map.hpp"

namespace sarmap::topo {

std::string graph_json(const TopoMap& map);
void write_graph_json(const std::filesystem::path& path, const TopoMap& map);
void write_graph_graphml(const std::filesystem::path& path, const TopoMap& map);
void write_graph_ply(const std::filesystem::path& path, const TopoMap& map);

struct GraphFile {
  TopoSettings settings;
  std::vector<TopoNode> nodes;  // indexed by id; ids missing from the file are retired nodes
  std::vector<TopoEdge> edges;
};
// Throws sarmap::Error (Io, Parse, InvalidData) naming the file, the entry and the key.
GraphFile read_graph_json(const std::filesystem::path& path);

std::string route_json(const Route& route);
void write_route_json(const std::filesystem::path& path, const Route& route);
// Reads what write_route_json wrote (`sarmap render` draws its points).
// Throws sarmap::Error (Io, Parse, InvalidData) naming the file and the key.
Route read_route_json(const std::filesystem::path& path);

}  // namespace sarmap::topo
