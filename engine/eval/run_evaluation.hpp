// Scores what `sarmap run` wrote in a folder against an arena's ground truth,
// as far as the folder allows: each output that is present is scored, each
// absent one is named. Formats the figures as a table and as JSON with plain
// keys (accuracy, mean_iou, per_class_iou, confusion, ...).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/eval/graph_scores.hpp"
#include "engine/eval/point_evaluation.hpp"
#include "engine/eval/segment_scores.hpp"
#include "engine/eval/voxel_scores.hpp"
#include "engine/sim/arena.hpp"

namespace sarmap::eval {

struct RunFile {
  std::string name;  // "semantic_points.ply", "map.sarmap", "segments.json", "graph.json"
  bool present = false;
};

struct RunEvaluation {
  std::string arena_name;
  std::filesystem::path run_dir;
  std::vector<RunFile> files;
  std::optional<PointEvaluation> points;  // from semantic_points.ply
  std::optional<VoxelScores> voxels;      // map.sarmap against the arena voxelised at its resolution
  // segments.json against the arena's faces, seen as the same voxelisation
  // says (at the map's resolution, or kSegmentTruthResolution without a map).
  std::optional<SegmentScores> segments;
  // graph.json: edges against the true walls, routes of the arena's pairs.
  std::optional<GraphScores> graph;
  std::vector<std::string> notes;          // what was not scored, and why
  // Whether the run's manifest named its arena (arena_sha256) and it was this
  // arena; false when the run records none (real data) and was scored unchecked.
  bool arena_checked = false;
};

// Resolution of the voxels that say which faces were seen when the run has no map.
inline constexpr double kSegmentTruthResolution = 0.05;

// Throws sarmap::Error: Io when run_dir is not a folder, InvalidData when its
// manifest.json is missing or a file it lists does not match it
// (engine/io/run_folder.hpp), InvalidArgument naming both hashes when the
// manifest's arena_sha256 (the arena a simulated input was rendered from) is
// not `arena`'s sha256. A run that records no arena is scored with a note
// saying it was not checked. Outputs the manifest does not list are absent.
RunEvaluation evaluate_run(const sim::Arena& arena, const std::filesystem::path& run_dir);

std::string format_table(const RunEvaluation& evaluation);
std::string format_json(const RunEvaluation& evaluation);
// The headline figures of format_json, under the same keys and with the same
// values, without its lists (confusion matrices, faces, crossing edges,
// route pairs): what `sarmap demo` adds to the run's summary.json as "eval".
nlohmann::ordered_json summary_json(const RunEvaluation& evaluation);

}  // namespace sarmap::eval
