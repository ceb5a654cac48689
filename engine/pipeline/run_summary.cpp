#include "engine/pipeline/run_summary.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <vector>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/geometry/triangle_scene.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/metric/map_summary.hpp"

namespace sarmap::pipeline {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

// Counters are summed as doubles; every one counted here is a whole number.
std::uint64_t count(const StageProfile& profile, std::string_view stage, std::string_view counter) {
  return static_cast<std::uint64_t>(profile.counter(stage, counter));
}

// To the microsecond: finer digits are noise, and they would fill the page.
double milliseconds(double seconds) { return std::round(seconds * 1e6) / 1e3; }

Json by_class(const std::array<std::size_t, kClassCount>& counts) {
  Json j = Json::object();
  for (std::size_t c = 0; c < kClassCount; ++c) j[std::string(kClassTable[c].name)] = counts[c];
  return j;
}

Json read_json_object(const fs::path& path) {
  std::ifstream in(path);
  Json j = Json::parse(in, nullptr, false);
  if (!in || j.is_discarded() || !j.is_object()) {
    throw Error(ErrorCode::InvalidData, path.string() + ": not a JSON object");
  }
  return j;
}

}  // namespace

Json run_summary_json(const Mapper& mapper) {
  const StageProfile& profile = mapper.profile();
  Json j;
  j["version"] = kRunSummaryVersion;
  j["scans"] = profile.scan_count();
  j["scans_skipped"] = profile.skipped_scans();
  j["points_in"] = count(profile, "preprocess", "points_in");
  j["points_out"] = count(profile, "preprocess", "points_out");
  j["wall_s"] = profile.wall_seconds();
  // As profile.json has it.
  j["scans_per_second"] =
      profile.wall_seconds() > 0 ? static_cast<double>(profile.scan_count()) / profile.wall_seconds() : 0.0;
  Json stages = Json::object();
  for (const std::string& name : profile.stage_names()) {
    const StageProfile::StageStats s = profile.stats(name);
    stages[name] = {{"mean_ms", milliseconds(s.mean_s)}, {"p95_ms", milliseconds(s.p95_s)}};
  }
  j["stages"] = std::move(stages);
  // From a scan's read to the end of its last stage (StageProfile::latency).
  const StageProfile::StageStats latency = profile.latency();
  j["latency"] = {{"p50_ms", milliseconds(latency.p50_s)}, {"p95_ms", milliseconds(latency.p95_s)}};

  const metric::MapSummary map = metric::summarize_map(mapper.metric_map());
  j["metric_map"] = {
      {"voxel", mapper.metric_map().resolution()}, {"blocks", map.counts.blocks},
      {"known_voxels", map.counts.known},          {"free_voxels", map.counts.free},
      {"occupied_voxels", map.counts.occupied},    {"occupied_by_class", by_class(map.occupied_by_class)},
      {"bytes", mapper.metric_map().memory_bytes()}};
  // What the classifier keeps beside the maps (the labelled point map and its
  // blocks, with the classifier of the accumulated map), to compare with the
  // metric map's bytes.
  if (const DgcnnMapClassifier* on_map = mapper.classifier().accumulated_map()) {
    // How many scans a new surface waits for its class (labels arrive late).
    const ClassDelays& delays = on_map->class_delays();
    j["labelled_point_map"] = {{"points", on_map->map().size()},
                               {"blocks", on_map->blocks().block_count()},
                               {"blocks_classified", on_map->blocks_classified()},
                               {"bytes", mapper.classifier().memory_bytes()},
                               {"scans_until_class",
                                {{"p50", delays.quantile(0.5)},
                                 {"p95", delays.quantile(0.95)},
                                 {"max", delays.quantile(1.0)},
                                 {"points", delays.recorded()},
                                 {"never", delays.waiting()}}}};
  }
  j["semantic_points"] = mapper.semantic_points().size();
  j["semantic_points_bytes"] = mapper.semantic_points_bytes();

  std::array<std::size_t, kClassCount> segments_by_class{};
  const std::vector<const segments::Segment*> segments = mapper.segment_map().segments();
  for (const segments::Segment* s : segments) ++segments_by_class[static_cast<std::size_t>(s->label)];
  j["segments"] = {{"count", segments.size()},
                   {"by_class", by_class(segments_by_class)},
                   {"points", mapper.segment_map().point_count()},
                   {"bytes", mapper.segment_map().memory_bytes()}};

  const topo::TopoMap& topo = mapper.topo_map();
  std::size_t nodes = 0, tree_edges = 0;
  for (const topo::TopoNode& n : topo.nodes()) nodes += n.alive;
  for (const topo::TopoEdge& e : topo.edges()) tree_edges += e.in_tree;
  // The spanning forest has one tree per component of the alive nodes.
  j["topo_map"] = {{"nodes", nodes},
                   {"roadmap_edges", topo.edges().size()},
                   {"tree_edges", tree_edges},
                   {"components", nodes - tree_edges},
                   {"bytes", topo.memory_bytes()},
                   {"embree_bytes", geometry::embree_bytes()}};
  return j;
}

void add_to_run_summary(const fs::path& folder, const std::string& key, const Json& value) {
  verify_run_folder(folder);
  Json manifest = read_json_object(folder / kRunManifestName);
  std::vector<std::string> outputs;
  bool listed = false;
  for (const Json& output : manifest.at("outputs")) {
    outputs.push_back(output.at("name").get<std::string>());
    listed = listed || outputs.back() == kRunSummaryName;
  }
  const fs::path summary_path = folder / kRunSummaryName;
  if (!listed) {
    throw Error(ErrorCode::InvalidData, (folder / kRunManifestName).string() +
                                            ": lists no summary.json (written by an older sarmap)");
  }
  Json summary = read_json_object(summary_path);
  if (summary.contains(key)) {
    throw Error(ErrorCode::InvalidArgument, summary_path.string() + ": already has \"" + key + "\"");
  }
  summary[key] = value;
  manifest.erase("outputs");  // commit() lists them again, last, as write_run's manifest has them

  RunFolderWriter writer(folder);  // the folder's lock; removes the manifest
  {
    AtomicFileWriter w(summary_path);
    w.write(summary.dump(2) + "\n");
    w.commit();
  }
  writer.commit(manifest, outputs);
}

}  // namespace sarmap::pipeline
