#include "engine/eval/run_evaluation.hpp"

#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/eval/optional_json_number.hpp"
#include "engine/io/ply.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/io/sha256.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/segments/segment_files.hpp"
#include "engine/topo/graph_files.hpp"
#include "engine/sim/ground_truth_grid.hpp"

namespace sarmap::eval {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kPointsFile = "semantic_points.ply";
constexpr const char* kMapFile = "map.sarmap";
constexpr const char* kSegmentsFile = "segments.json";
constexpr const char* kGraphFile = "graph.json";

std::string percent(const std::optional<double>& v) {
  if (!v) return "n/a";
  char text[32];
  std::snprintf(text, sizeof text, "%.2f%%", 100.0 * *v);
  return text;
}

// The ground truth counts what the whole trajectory sees; a run of fewer
// frames (simulate --frames) is held to that, so say so.
void note_partial_run(const sim::Arena& arena, const std::filesystem::path& run_dir,
                      std::vector<std::string>& notes) {
  std::ifstream in(run_dir / "manifest.json");
  if (!in) return;
  const Json manifest = Json::parse(in, nullptr, false);
  const bool has_scans = !manifest.is_discarded() && manifest.contains("scans");
  if (!has_scans || !manifest["scans"].is_number_unsigned()) return;
  const auto scans = manifest["scans"].get<std::size_t>();
  const std::size_t frames =
      arena.trajectory.waypoints.empty() ? arena.trajectory.poses.size() : arena.trajectory.frames;
  if (scans < frames) {
    notes.push_back("the run holds " + std::to_string(scans) + " of the trajectory's " +
                    std::to_string(frames) +
                    " frames; voxel recall, free accuracy and seen faces count what all of them see");
  }
}

// Figures against another arena than the run's mean nothing (a recall near
// 0 that looks like a bad map), so a run whose manifest names its arena is
// refused any other. Returns whether the arena was checked.
bool check_arena(const sim::Arena& arena, const std::filesystem::path& run_dir,
                 std::vector<std::string>& notes) {
  const std::filesystem::path path = run_dir / "manifest.json";
  std::ifstream in(path);
  const Json manifest = Json::parse(in, nullptr, false);  // verify_run_folder read it already
  const auto it = manifest.is_object() ? manifest.find("arena_sha256") : manifest.end();
  if (it == manifest.end() || it->is_null()) {
    notes.push_back(
        "the run's input records no arena (not simulated, or simulated before sequences recorded "
        "their arena): not checked that it was mapped from " +
        arena.source);
    return false;
  }
  if (!it->is_string() || !is_sha256_hex(it->get<std::string>())) {
    throw Error(ErrorCode::InvalidData,
                path.string() + ": arena_sha256: expected 64 lowercase hex digits, got " + it->dump());
  }
  const std::string recorded = it->get<std::string>();
  if (arena.sha256.empty()) {
    notes.push_back(
        "the arena was not read from a file (no sha256): not checked against the run's arena_sha256 " +
        recorded);
    return false;
  }
  if (recorded != arena.sha256) {
    std::string input;
    if (manifest.contains("input") && manifest["input"].is_object() && manifest["input"].contains("path") &&
        manifest["input"]["path"].is_string()) {
      input = " " + manifest["input"]["path"].get<std::string>();
    }
    throw Error(ErrorCode::InvalidArgument,
                "run " + run_dir.string() + " was mapped from a sequence" + input +
                    " simulated from the arena with sha256 " + recorded +
                    " (manifest.json's arena_sha256), but arena " + arena.source + " (\"" + arena.name +
                    "\") has sha256 " + arena.sha256 +
                    ": score the run against the arena its sequence was simulated from");
  }
  return true;
}

}  // namespace

RunEvaluation evaluate_run(const sim::Arena& arena, const std::filesystem::path& run_dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(run_dir, ec)) {
    throw Error(ErrorCode::Io, run_dir.string() + ": run folder not found");
  }
  verify_run_folder(run_dir);  // a half-written or mixed folder is refused, not scored
  RunEvaluation e;
  e.arena_checked = check_arena(arena, run_dir, e.notes);
  e.arena_name = arena.name;
  e.run_dir = run_dir;
  for (const char* name : {kPointsFile, kMapFile, kSegmentsFile, kGraphFile}) {
    e.files.push_back({name, std::filesystem::is_regular_file(run_dir / name, ec)});
  }
  const auto present = [&e](const char* name) {
    for (const RunFile& f : e.files) {
      if (f.name == name) return f.present;
    }
    return false;
  };
  if (present(kPointsFile)) {
    const std::filesystem::path path = run_dir / kPointsFile;
    e.points = evaluate_points(read_ply(path), path.string());
  } else {
    e.notes.push_back(std::string(kPointsFile) + " absent: no per-point figures");
  }
  // One voxelisation (its visibility rays are most of eval's time) serves
  // the voxel and the segment figures.
  std::optional<sim::GroundTruthGrid> truth;
  const auto truth_at = [&](double resolution) -> const sim::GroundTruthGrid& {
    if (!truth) {
      sim::GroundTruthOptions truth_options;
      truth_options.resolution = resolution;
      truth = sim::voxelize_arena(arena, truth_options);
    }
    return *truth;
  };
  std::optional<metric::MetricMap> map;
  if (present(kMapFile)) {
    map = metric::load_map(run_dir / kMapFile);
    e.voxels = score_voxels(*map, truth_at(map->resolution()));
  } else {
    e.notes.push_back(std::string(kMapFile) + " absent: no voxel figures");
  }
  std::optional<segments::SegmentsFile> segments_file;
  if (present(kSegmentsFile)) {
    segments_file = segments::read_segments_json(run_dir / kSegmentsFile);
    e.segments = score_segments(arena, truth_at(kSegmentTruthResolution), segments_file->segments);
  } else {
    e.notes.push_back(std::string(kSegmentsFile) + " absent: no segment figures");
  }
  if (truth) note_partial_run(arena, run_dir, e.notes);
  if (present(kGraphFile)) {
    topo::GraphFile graph = topo::read_graph_json(run_dir / kGraphFile);
    // Routes need the wall scene and the grid the run planned on.
    std::optional<topo::TopoMap> routes;
    if (map && segments_file) {
      std::vector<const segments::Segment*> segments;
      for (const segments::Segment& s : segments_file->segments) segments.push_back(&s);
      routes = topo::TopoMap::restore(graph.settings, graph.nodes, graph.edges, segments, *map);
    } else {
      e.notes.push_back("graph.json without map.sarmap and segments.json: edge figures only, no path figures");
    }
    e.graph = score_graph(arena, graph, routes ? &*routes : nullptr);
  } else {
    e.notes.push_back(std::string(kGraphFile) + " absent: no graph or path figures");
  }
  return e;
}

namespace {

// Every figure, as `sarmap eval --json` prints it.
Json to_json(const RunEvaluation& e) {
  Json j;
  j["arena"] = e.arena_name;
  j["run"] = e.run_dir.string();
  j["arena_checked"] = e.arena_checked;
  Json files = Json::object();
  Json absent = Json::array();
  for (const RunFile& f : e.files) {
    files[f.name] = f.present;
    if (!f.present) absent.push_back(f.name);
  }
  j["files"] = files;
  j["absent"] = absent;
  if (e.points) {
    const ConfusionMatrix& m = e.points->confusion;
    j["points"] = e.points->points;
    j["points_scored"] = e.points->scored;
    j["points_unlabelled"] = e.points->unlabelled;
    j["accuracy"] = optional_json_number(m.accuracy());
    j["mean_iou"] = optional_json_number(m.mean_iou());
    Json per_class = Json::object();
    for (std::size_t c = 1; c < kClassCount; ++c) {
      per_class[std::string(kClassTable[c].name)] = optional_json_number(m.iou(static_cast<ClassId>(c)));
    }
    j["per_class_iou"] = per_class;
    Json classes = Json::array();
    Json matrix = Json::array();
    for (std::size_t t = 0; t < kClassCount; ++t) {
      classes.push_back(kClassTable[t].name);
      Json row = Json::array();
      for (std::size_t p = 0; p < kClassCount; ++p) row.push_back(m.count(static_cast<ClassId>(t), static_cast<ClassId>(p)));
      matrix.push_back(row);
    }
    j["confusion"] = {{"classes", classes}, {"rows", "ground truth"}, {"columns", "prediction"}, {"matrix", matrix}};
  }
  if (e.voxels) add_voxel_scores_json(*e.voxels, j);
  if (e.segments) add_segment_scores_json(*e.segments, j);
  if (e.graph) add_graph_scores_json(*e.graph, j);
  j["notes"] = e.notes;
  return j;
}

}  // namespace

std::string format_json(const RunEvaluation& e) { return to_json(e).dump(2) + "\n"; }

Json summary_json(const RunEvaluation& e) {
  const Json all = to_json(e);
  const auto pick = [](const Json& from, std::initializer_list<const char*> keys) {
    Json picked = Json::object();
    for (const char* key : keys) {
      if (from.contains(key)) picked[key] = from[key];
    }
    return picked;
  };
  Json j = pick(all, {"arena", "arena_checked", "points_scored", "accuracy", "mean_iou", "per_class_iou",
                      "voxel_resolution", "voxel_precision", "voxel_recall", "voxel_f1",
                      "voxel_precision_within_1", "voxel_recall_within_1", "voxel_f1_within_1",
                      "free_accuracy", "free_precision", "voxel_class_accuracy"});
  if (all.contains("segments")) {
    j["segments"] = pick(all["segments"],
                         {"segment_count", "counted", "seen", "matched", "missed", "split", "on_sides",
                          "spurious", "max_normal_error_deg", "max_offset_error_m", "max_slope_error_deg"});
  }
  if (all.contains("graph")) {
    j["graph"] = pick(all["graph"],
                      {"nodes", "edges", "tree_edges", "edges_crossing_walls", "tree_edges_crossing_walls"});
  }
  j["notes"] = all["notes"];
  return j;
}

std::string format_table(const RunEvaluation& e) {
  std::ostringstream out;
  out << "arena " << e.arena_name << ", run " << e.run_dir.string() << "\n";
  for (const RunFile& f : e.files) out << "  " << f.name << ": " << (f.present ? "present" : "absent") << "\n";
  if (e.points) {
    const ConfusionMatrix& m = e.points->confusion;
    out << "\nper-point classification (" << kPointsFile << "): " << e.points->scored << " of " << e.points->points
        << " points scored, " << e.points->unlabelled << " unlabelled\n";
    out << "  accuracy  " << percent(m.accuracy()) << "\n";
    out << "  mean IoU  " << percent(m.mean_iou()) << "  (terrain, wall, inclined ramp, flat ramp)\n";
    char line[160];
    std::snprintf(line, sizeof line, "  %-14s %9s %9s %9s\n", "class", "IoU", "precision", "recall");
    out << line;
    for (std::size_t c = 1; c < kClassCount; ++c) {
      const auto id = static_cast<ClassId>(c);
      std::snprintf(line, sizeof line, "  %-14s %9s %9s %9s\n", std::string(kClassTable[c].name).c_str(),
                    percent(m.iou(id)).c_str(), percent(m.precision(id)).c_str(), percent(m.recall(id)).c_str());
      out << line;
    }
    out << "\n  confusion (rows: ground truth, columns: prediction)\n  " << std::string(14, ' ');
    for (std::size_t p = 0; p < kClassCount; ++p) {
      std::snprintf(line, sizeof line, " %13s", std::string(kClassTable[p].name).c_str());
      out << line;
    }
    out << "\n";
    for (std::size_t t = 0; t < kClassCount; ++t) {
      std::snprintf(line, sizeof line, "  %-14s", std::string(kClassTable[t].name).c_str());
      out << line;
      for (std::size_t p = 0; p < kClassCount; ++p) {
        std::snprintf(line, sizeof line, " %13llu",
                      static_cast<unsigned long long>(m.count(static_cast<ClassId>(t), static_cast<ClassId>(p))));
        out << line;
      }
      out << "\n";
    }
  }
  if (e.voxels) out << "\n" << format_voxel_scores(*e.voxels);
  if (e.segments) out << "\n" << format_segment_scores(*e.segments);
  if (e.graph) out << "\n" << format_graph_scores(*e.graph);
  if (!e.notes.empty()) {
    out << "\n";
    for (const std::string& n : e.notes) out << "note: " << n << "\n";
  }
  return out.str();
}

}  // namespace sarmap::eval
