// Reads a run folder's outputs into the viewer's layers (view_data.hpp):
// semantic points, occupied and free voxels, segments, the graph, a planned
// route and the sensor's path, each thinned to the point budget.
#include "tools/sarmap/view_data.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/io/json_fields.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/sarmap_sequence_manifest.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/segments/segment_files.hpp"
#include "engine/topo/graph_files.hpp"
#include "engine/topo/node_placement.hpp"

namespace sarmap::cli {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

Json vec3(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

template <class T>
std::string base64_of(const std::vector<T>& values) {
  return base64(values.data(), values.size() * sizeof(T));
}

// Indices of `total` items kept under the budget: every one, or an even
// spread that keeps the first, so a thinned layer still covers the map.
std::vector<std::size_t> kept_indices(std::size_t total, std::size_t budget) {
  std::vector<std::size_t> kept;
  const std::size_t count = std::min(total, budget);
  kept.reserve(count);
  for (std::size_t i = 0; i < count; ++i) kept.push_back(count == total ? i : i * total / count);
  return kept;
}

// The common part of the two point layers: positions of the kept points and
// their labels (class 0 when the file has none).
Json point_layer(const PointBuffer& points, const std::vector<std::size_t>& kept) {
  std::vector<float> positions;
  std::vector<std::uint8_t> labels;
  positions.reserve(kept.size() * 3);
  labels.reserve(kept.size());
  for (const std::size_t i : kept) {
    positions.insert(positions.end(), {points.x()[i], points.y()[i], points.z()[i]});
    labels.push_back(points.has_labels() ? points.labels()[i] : 0);
  }
  return Json{{"count", kept.size()},
              {"total", points.size()},
              {"positions", base64_of(positions)},
              {"labels", base64_of(labels)}};
}

// The voxel edge voxels.ply's header names ("voxel_size 0.05"); 0 when absent.
double voxel_size_of(const PointCloudFileInfo& info) {
  constexpr std::string_view kKey = "voxel_size ";
  for (const std::string& comment : info.comments) {
    if (comment.rfind(kKey, 0) != 0) continue;
    try {
      return std::stod(comment.substr(kKey.size()));
    } catch (const std::exception&) {
      return 0;
    }
  }
  return 0;
}

Json voxels_layer(const fs::path& file, std::size_t budget) {
  PointCloudFileInfo info;
  const PointBuffer voxels = read_point_cloud(file, &info);
  const double size = voxel_size_of(info);
  if (!(size > 0)) {
    throw Error(ErrorCode::InvalidData, file.string() + ": no 'comment voxel_size' line in the header");
  }
  const std::vector<std::size_t> kept = kept_indices(voxels.size(), budget);
  Json layer = point_layer(voxels, kept);
  layer["size"] = size;
  const std::size_t channel = voxels.find_score("probability");
  if (channel < voxels.score_count()) {
    std::vector<float> probabilities;
    probabilities.reserve(kept.size());
    for (const std::size_t i : kept) probabilities.push_back(voxels.score(channel)[i]);
    layer["probabilities"] = base64_of(probabilities);
  }
  // The index in voxels.ply, so a picked cube names the voxel the file holds.
  std::vector<std::uint32_t> ids;
  ids.reserve(kept.size());
  for (const std::size_t i : kept) ids.push_back(static_cast<std::uint32_t>(i));
  layer["ids"] = base64_of(ids);
  return layer;
}

// Free voxels thinned on a coarser lattice (every s-th voxel along each axis)
// rather than by file order, so what is left is evenly spread in space.
Json free_layer(const fs::path& file, std::size_t budget) {
  const metric::MetricMap map = metric::load_map(file);
  constexpr int kMaxStride = 16;
  std::vector<metric::VoxelKey> free;
  for (const metric::BlockKey& bk : map.blocks().sorted_block_keys()) {
    const auto& block = *map.blocks().find(bk);
    for (int local = 0; local < metric::kBlockVoxels; ++local) {
      if (map.occupancy().state(block.log_odds(local)) == metric::VoxelState::Free) {
        free.push_back(metric::voxel_of(bk, local));
      }
    }
  }
  const auto on_lattice = [](const metric::VoxelKey& k, int s) {
    const auto mod = [s](std::int32_t c) { return ((c % s) + s) % s; };
    return mod(k.x) == 0 && mod(k.y) == 0 && mod(k.z) == 0;
  };
  const auto count_on_lattice = [&](int s) {
    return static_cast<std::size_t>(
        std::count_if(free.begin(), free.end(), [&](const metric::VoxelKey& k) { return on_lattice(k, s); }));
  };
  int stride = 1;
  while (stride < kMaxStride && count_on_lattice(stride) > budget) ++stride;
  std::vector<metric::VoxelKey> lattice;
  for (const metric::VoxelKey& k : free) {
    if (on_lattice(k, stride)) lattice.push_back(k);
  }
  std::vector<float> positions;
  for (const std::size_t i : kept_indices(lattice.size(), budget)) {
    const Eigen::Vector3d c = map.center_of(lattice[i]);
    positions.insert(positions.end(),
                     {static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z())});
  }
  return Json{{"count", positions.size() / 3},
              {"total", free.size()},
              {"size", map.resolution()},
              {"stride", stride},
              {"positions", base64_of(positions)}};
}

Json segments_layer(const std::vector<segments::Segment>& segments) {
  Json items = Json::array();
  for (const segments::Segment& s : segments) {
    items.push_back(
        Json{{"id", s.id},
             {"class_id", static_cast<int>(s.label)},
             {"center", vec3(s.rectangle.center)},
             {"axes", Json::array({vec3(s.rectangle.axes[0]), vec3(s.rectangle.axes[1])})},
             {"half_extents", Json::array({s.rectangle.half_extents[0], s.rectangle.half_extents[1]})},
             {"area_m2", s.area_m2},
             {"slope_deg", s.slope_deg},
             {"inliers", s.inliers}});
  }
  return Json{{"count", items.size()}, {"items", std::move(items)}};
}

// Nodes and edges are two layers: the nodes pickable, the edges drawn by node id.
void graph_layers(const fs::path& file, const std::vector<segments::Segment>& segments, Json& layers) {
  const topo::GraphFile graph = topo::read_graph_json(file);
  Json nodes = Json::array();
  for (const topo::TopoNode& n : graph.nodes) {
    if (!n.alive) continue;
    int class_id = 0;
    for (const segments::Segment& s : segments) {
      if (s.id == n.segment) class_id = static_cast<int>(s.label);
    }
    nodes.push_back(Json{{"id", n.id},
                         {"pos", vec3(n.position)},
                         {"kind", std::string(topo::to_string(n.kind))},
                         {"segment", n.segment},
                         {"class_id", class_id}});
  }
  Json edges = Json::array();
  for (const topo::TopoEdge& e : graph.edges) edges.push_back(Json::array({e.a, e.b, e.in_tree ? 1 : 0}));
  layers["nodes"] = Json{{"count", nodes.size()}, {"items", std::move(nodes)}};
  layers["edges"] = Json{{"count", edges.size()}, {"pairs", std::move(edges)}};
}

// path.json as `sarmap plan --out` writes it; a route not found draws nothing.
Json path_layer(const fs::path& file, std::vector<std::string>& notes) {
  const topo::Route route = topo::read_route_json(file);
  if (!route.found) {
    notes.push_back(file.string() + " holds no path (" + route.reason + "), so no path is drawn");
    return nullptr;
  }
  Json points = Json::array();
  for (const Eigen::Vector3d& p : route.points) points.push_back(vec3(p));
  return Json{
      {"count", points.size()},
      {"points", std::move(points)},
      {"length", route.length},
      {"graph", std::string(topo::to_string(route.graph))},
      {"algorithm", route.graph == topo::RouteGraph::Grid ? std::string("wavefront")
                                                          : std::string(topo::to_string(route.search))}};
}

// The sensor's positions, from the sequence the run read (manifest.json's
// input): the run itself records no poses. Only sarmap's own sequence folder
// is read, through its sequence.json, without loading a frame.
Json trajectory_layer(const fs::path& manifest_file, std::vector<std::string>& notes) {
  const Json manifest = json_fields::read_file(manifest_file);
  const Json& input = json_fields::member(manifest, "input", manifest_file, "manifest");
  const Json& path = json_fields::member(input, "path", manifest_file, "input");
  const Json& layout = json_fields::member(manifest, "layout", manifest_file, "manifest");
  if (!layout.is_string()) json_fields::fail(manifest_file, "manifest", "'layout' must be a string");
  if (layout.get<std::string>() == "arrays") {
    // Scans handed over as arrays (the Python module): no file holds the poses.
    notes.push_back(
        "the run's scans were given as arrays, not read from a sequence folder: no trajectory is drawn");
    return nullptr;
  }
  if (layout.get<std::string>() == "merged") {
    // Several runs' maps (`sarmap merge`): their trajectories are in their own frames.
    notes.push_back("the run merges several runs' maps: no trajectory is drawn");
    return nullptr;
  }
  if (!path.is_string()) json_fields::fail(manifest_file, "manifest", "'input.path' must be a string");
  if (layout.get<std::string>() != "sarmap") {
    if (layout.get<std::string>() != "cloud") {
      notes.push_back("the trajectory is drawn for sarmap sequence folders only, not for a " +
                      layout.get<std::string>() + " input");
    }
    return nullptr;
  }
  const fs::path sequence = fs::path(path.get<std::string>()) / "sequence.json";
  std::error_code ec;
  if (!fs::is_regular_file(sequence, ec)) {
    notes.push_back("the run's input " + sequence.string() + " is gone, so no trajectory is drawn");
    return nullptr;
  }
  const SequenceManifest frames = read_sequence_manifest(sequence);
  Json points = Json::array();
  for (const SequenceManifestFrame& f : frames.frames) points.push_back(vec3(f.origin));
  return Json{{"count", points.size()}, {"points", std::move(points)}};
}

bool is_file(const fs::path& file) {
  std::error_code ec;
  return fs::is_regular_file(file, ec);
}

}  // namespace

std::string base64(const void* data, std::size_t size) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const std::uint32_t word = (bytes[i] << 16) | (bytes[i + 1] << 8) | bytes[i + 2];
    for (int shift = 18; shift >= 0; shift -= 6) out += kDigits[(word >> shift) & 63];
  }
  if (i < size) {
    const std::uint32_t word = (bytes[i] << 16) | (i + 1 < size ? bytes[i + 1] << 8 : 0);
    out += kDigits[(word >> 18) & 63];
    out += kDigits[(word >> 12) & 63];
    out += i + 1 < size ? kDigits[(word >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

ViewData read_view_data(const fs::path& run, const ViewDataOptions& options) {
  ViewData view;
  Json classes = Json::array();
  for (const ClassInfo& c : kClassTable) {
    classes.push_back(Json{{"id", static_cast<int>(c.id)},
                           {"name", std::string(c.name)},
                           {"label", std::string(c.display_name)},
                           {"color", Json::array({c.color.r, c.color.g, c.color.b})}});
  }
  Json layers = Json::object();
  if (is_file(run / "semantic_points.ply")) {
    const PointBuffer points = read_point_cloud(run / "semantic_points.ply");
    layers["points"] = point_layer(points, kept_indices(points.size(), options.max_items));
  }
  if (is_file(run / "voxels.ply")) layers["voxels"] = voxels_layer(run / "voxels.ply", options.max_items);
  if (is_file(run / "map.sarmap")) layers["free"] = free_layer(run / "map.sarmap", options.max_items);
  std::vector<segments::Segment> segments;
  if (is_file(run / "segments.json")) {
    segments = segments::read_segments_json(run / "segments.json").segments;
    layers["segments"] = segments_layer(segments);
  }
  if (is_file(run / "graph.json")) graph_layers(run / "graph.json", segments, layers);
  if (!options.path_file.empty()) {
    if (Json path = path_layer(options.path_file, view.notes); !path.is_null())
      layers["path"] = std::move(path);
  }
  if (Json trajectory = trajectory_layer(run / "manifest.json", view.notes); !trajectory.is_null()) {
    layers["trajectory"] = std::move(trajectory);
  }
  view.json = Json{{"version", 1},
                   {"run", run.filename().string()},
                   {"classes", std::move(classes)},
                   {"layers", std::move(layers)}};
  return view;
}

}  // namespace sarmap::cli
