#include "engine/topo/graph_files.hpp"

#include <cstdio>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/json_fields.hpp"
#include "engine/io/ply_mesh.hpp"

namespace sarmap::topo {
namespace {

using json_fields::Json;
using json_fields::fail;
using json_fields::member;
using json_fields::number;

Json settings_json(const TopoSettings& s) {
  return {{"robot_radius", s.robot_radius},   {"robot_height", s.robot_height},
          {"body_heights", s.body_heights},   {"max_slope_deg", s.max_slope_deg},
          {"max_step", s.max_step},           {"node_spacing", s.node_spacing},
          {"edge_radius", s.edge_radius},     {"obstacle_voxels", s.obstacle_voxels},
          {"unknown_traversable", s.unknown_traversable}};
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  AtomicFileWriter out(path);
  out.write(text);
  out.commit();
}

std::uint32_t id_of(const Json& j, const char* key, const std::filesystem::path& path, const std::string& where) {
  const Json& v = member(j, key, path, where);
  if (!v.is_number_unsigned() || v.get<std::uint64_t>() > 0xfffffffeull) {
    fail(path, where, std::string("\"") + key + "\" is not a node id");
  }
  return v.get<std::uint32_t>();
}

TopoSettings parse_settings(const Json& g, const std::filesystem::path& path) {
  TopoSettings s;
  const std::string where = "graph";
  s.robot_radius = number(g, "robot_radius", path, where);
  s.robot_height = number(g, "robot_height", path, where);
  const Json& heights = member(g, "body_heights", path, where);
  if (!heights.is_array()) fail(path, where, "\"body_heights\" is not an array");
  s.body_heights.clear();
  for (const Json& h : heights) {
    if (!h.is_number()) fail(path, where, "\"body_heights\" holds a non-number");
    s.body_heights.push_back(h.get<double>());
  }
  s.max_slope_deg = number(g, "max_slope_deg", path, where);
  s.max_step = number(g, "max_step", path, where);
  s.node_spacing = number(g, "node_spacing", path, where);
  s.edge_radius = number(g, "edge_radius", path, where);
  const Json& voxels = member(g, "obstacle_voxels", path, where);
  const Json& unknown = member(g, "unknown_traversable", path, where);
  if (!voxels.is_boolean() || !unknown.is_boolean()) fail(path, where, "obstacle_voxels and unknown_traversable are true or false");
  s.obstacle_voxels = voxels.get<bool>();
  s.unknown_traversable = unknown.get<bool>();
  try {
    validate(s);
  } catch (const Error& e) {
    fail(path, where, e.what());
  }
  return s;
}

Json point_json(const Eigen::Vector3d& p) { return Json::array({p.x(), p.y(), p.z()}); }

std::string xml_number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

}  // namespace

std::string graph_json(const TopoMap& map) {
  Json j;
  j["directed"] = false;
  j["multigraph"] = false;
  j["graph"] = settings_json(map.settings());
  j["nodes"] = Json::array();
  for (const TopoNode& n : map.nodes()) {
    if (!n.alive) continue;
    j["nodes"].push_back(
        {{"id", n.id}, {"pos", point_json(n.position)}, {"kind", to_string(n.kind)}, {"segment", n.segment}});
  }
  j["links"] = Json::array();
  for (const TopoEdge& e : map.edges()) {
    j["links"].push_back({{"source", e.a},
                          {"target", e.b},
                          {"length", e.length},
                          {"slope_deg", e.slope_deg},
                          {"ground", class_info(e.ground).name},
                          {"in_tree", e.in_tree}});
  }
  return j.dump(1) + "\n";
}

void write_graph_json(const std::filesystem::path& path, const TopoMap& map) { write_text(path, graph_json(map)); }

void write_graph_graphml(const std::filesystem::path& path, const TopoMap& map) {
  std::string x =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<graphml xmlns=\"http://graphml.graphdrawing.org/xmlns\">\n"
      "  <key id=\"x\" for=\"node\" attr.name=\"x\" attr.type=\"double\"/>\n"
      "  <key id=\"y\" for=\"node\" attr.name=\"y\" attr.type=\"double\"/>\n"
      "  <key id=\"z\" for=\"node\" attr.name=\"z\" attr.type=\"double\"/>\n"
      "  <key id=\"kind\" for=\"node\" attr.name=\"kind\" attr.type=\"string\"/>\n"
      "  <key id=\"segment\" for=\"node\" attr.name=\"segment\" attr.type=\"long\"/>\n"
      "  <key id=\"length\" for=\"edge\" attr.name=\"length\" attr.type=\"double\"/>\n"
      "  <key id=\"slope_deg\" for=\"edge\" attr.name=\"slope_deg\" attr.type=\"double\"/>\n"
      "  <key id=\"ground\" for=\"edge\" attr.name=\"ground\" attr.type=\"string\"/>\n"
      "  <key id=\"in_tree\" for=\"edge\" attr.name=\"in_tree\" attr.type=\"boolean\"/>\n"
      "  <graph id=\"sarmap\" edgedefault=\"undirected\">\n";
  for (const TopoNode& n : map.nodes()) {
    if (!n.alive) continue;
    x += "    <node id=\"" + std::to_string(n.id) + "\"><data key=\"x\">" + xml_number(n.position.x()) +
         "</data><data key=\"y\">" + xml_number(n.position.y()) + "</data><data key=\"z\">" +
         xml_number(n.position.z()) + "</data><data key=\"kind\">" + std::string(to_string(n.kind)) +
         "</data><data key=\"segment\">" + std::to_string(n.segment) + "</data></node>\n";
  }
  for (const TopoEdge& e : map.edges()) {
    x += "    <edge source=\"" + std::to_string(e.a) + "\" target=\"" + std::to_string(e.b) +
         "\"><data key=\"length\">" + xml_number(e.length) + "</data><data key=\"slope_deg\">" +
         xml_number(e.slope_deg) + "</data><data key=\"ground\">" + std::string(class_info(e.ground).name) +
         "</data><data key=\"in_tree\">" + (e.in_tree ? "true" : "false") + "</data></edge>\n";
  }
  x += "  </graph>\n</graphml>\n";
  write_text(path, x);
}

void write_graph_ply(const std::filesystem::path& path, const TopoMap& map) {
  ColoredMesh mesh;
  std::vector<std::uint32_t> vertex_of(map.nodes().size(), 0);
  for (const TopoNode& n : map.nodes()) {
    if (!n.alive) continue;
    vertex_of[n.id] = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(n.position.cast<float>());
    const ClassId ground = n.kind == NodeKind::FlatRamp ? ClassId::FlatRamp
                           : n.kind == NodeKind::Terrain ? ClassId::Terrain
                                                         : ClassId::InclinedRamp;
    mesh.vertex_colors.push_back(class_info(ground).color);
  }
  for (const TopoEdge& e : map.edges()) {
    mesh.edges.push_back({vertex_of[e.a], vertex_of[e.b]});
    mesh.edge_colors.push_back(e.in_tree ? Rgb{0, 0, 0} : Rgb{160, 160, 160});
  }
  write_ply_mesh(path, mesh);
}

GraphFile read_graph_json(const std::filesystem::path& path) {
  const Json j = json_fields::read_file(path);
  GraphFile file;
  file.settings = parse_settings(member(j, "graph", path, "top level"), path);
  const Json& nodes = member(j, "nodes", path, "top level");
  const Json& links = member(j, "links", path, "top level");
  if (!nodes.is_array() || !links.is_array()) fail(path, "top level", "\"nodes\" and \"links\" must be arrays");
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const std::string where = "nodes[" + std::to_string(i) + "]";
    TopoNode n;
    n.id = id_of(nodes[i], "id", path, where);
    n.position = json_fields::vector3(member(nodes[i], "pos", path, where), "pos", path, where);
    if (!n.position.allFinite()) fail(path, where, "\"pos\" is not finite");
    const Json& kind = member(nodes[i], "kind", path, where);
    bool known = false;
    for (NodeKind k : {NodeKind::Terrain, NodeKind::FlatRamp, NodeKind::RampFoot, NodeKind::RampTop}) {
      if (kind.is_string() && kind.get<std::string>() == to_string(k)) {
        n.kind = k;
        known = true;
      }
    }
    if (!known) fail(path, where, "\"kind\" is not terrain, flat_ramp, ramp_foot or ramp_top");
    n.segment = id_of(nodes[i], "segment", path, where);
    if (n.id < file.nodes.size() && file.nodes[n.id].alive) fail(path, where, "node id " + std::to_string(n.id) + " repeats");
    if (n.id >= file.nodes.size()) {
      const std::size_t before = file.nodes.size();
      file.nodes.resize(n.id + 1);
      for (std::size_t k = before; k < file.nodes.size(); ++k) {
        file.nodes[k].id = static_cast<std::uint32_t>(k);
        file.nodes[k].alive = false;
      }
    }
    n.alive = true;
    file.nodes[n.id] = n;
  }
  for (std::size_t i = 0; i < links.size(); ++i) {
    const std::string where = "links[" + std::to_string(i) + "]";
    TopoEdge e;
    e.a = id_of(links[i], "source", path, where);
    e.b = id_of(links[i], "target", path, where);
    if (e.a >= file.nodes.size() || e.b >= file.nodes.size() || !file.nodes[e.a].alive || !file.nodes[e.b].alive) {
      fail(path, where, "joins a node the file does not list");
    }
    e.length = number(links[i], "length", path, where);
    const double straight = (file.nodes[e.a].position - file.nodes[e.b].position).norm();
    if (!(std::abs(e.length - straight) <= 1e-6 * std::max(1.0, straight))) {
      fail(path, where, "\"length\" is not the distance between its nodes");
    }
    e.slope_deg = number(links[i], "slope_deg", path, where);
    const Json& ground = member(links[i], "ground", path, where);
    const auto c = ground.is_string() ? class_from_name(ground.get<std::string>()) : std::nullopt;
    if (!c) fail(path, where, "\"ground\" is not a class name");
    e.ground = *c;
    const Json& tree = member(links[i], "in_tree", path, where);
    if (!tree.is_boolean()) fail(path, where, "\"in_tree\" is not true or false");
    e.in_tree = tree.get<bool>();
    file.edges.push_back(e);
  }
  return file;
}

std::string route_json(const Route& r) {
  Json j;
  j["found"] = r.found;
  if (!r.found) j["reason"] = r.reason;
  j["graph"] = to_string(r.graph);
  j["algorithm"] = r.graph == RouteGraph::Grid ? std::string("wavefront") : std::string(to_string(r.search));
  j["length"] = r.length;
  j["points"] = Json::array();
  for (const Eigen::Vector3d& p : r.points) j["points"].push_back(point_json(p));
  if (r.graph != RouteGraph::Grid) j["nodes"] = r.nodes;
  return j.dump(1) + "\n";
}

void write_route_json(const std::filesystem::path& path, const Route& route) { write_text(path, route_json(route)); }

Route read_route_json(const std::filesystem::path& path) {
  const Json j = json_fields::read_file(path);
  const std::string where = "top level";
  Route r;
  const Json& found = member(j, "found", path, where);
  if (!found.is_boolean()) fail(path, where, "\"found\" is not true or false");
  r.found = found.get<bool>();
  if (!r.found) {
    const Json& reason = member(j, "reason", path, where);
    if (!reason.is_string()) fail(path, where, "\"reason\" is not a string");
    r.reason = reason.get<std::string>();
  }
  const Json& graph = member(j, "graph", path, where);
  const auto g = graph.is_string() ? route_graph_from(graph.get<std::string>()) : std::nullopt;
  if (!g) fail(path, where, "\"graph\" is not tree, roadmap or grid");
  r.graph = *g;
  const Json& algorithm = member(j, "algorithm", path, where);
  if (!algorithm.is_string()) fail(path, where, "\"algorithm\" is not a string");
  const std::string name = algorithm.get<std::string>();
  const auto search = route_search_from(name);
  if (r.graph == RouteGraph::Grid ? name != "wavefront" : !search) {
    fail(path, where, "\"algorithm\" is not dijkstra or astar (wavefront on the grid)");
  }
  if (search) r.search = *search;
  r.length = number(j, "length", path, where);
  const Json& points = member(j, "points", path, where);
  if (!points.is_array()) fail(path, where, "\"points\" is not an array");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p =
        json_fields::vector3(points[i], "points[" + std::to_string(i) + "]", path, where);
    if (!p.allFinite()) fail(path, where, "\"points[" + std::to_string(i) + "]\" is not finite");
    r.points.push_back(p);
  }
  if (r.graph != RouteGraph::Grid) {
    const Json& nodes = member(j, "nodes", path, where);
    if (!nodes.is_array()) fail(path, where, "\"nodes\" is not an array");
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      r.nodes.push_back(id_of(Json{{"id", nodes[i]}}, "id", path, "nodes[" + std::to_string(i) + "]"));
    }
  }
  return r;
}

}  // namespace sarmap::topo
