// summary.json: a run's headline figures on one page (scans, points, speed,
// per-stage times, map sizes, segment and node counts), taken from the
// Mapper and its profile as they stand; write_run writes it with the other
// outputs. A front end that scores the run (`sarmap demo`) adds its figures
// with add_to_run_summary, which commits the folder again (docs/formats.md).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "engine/pipeline/mapper.hpp"

namespace sarmap::pipeline {

inline constexpr int kRunSummaryVersion = 1;
inline constexpr std::string_view kRunSummaryName = "summary.json";

// The summary of `mapper` as it stands: {"version", "scans", "scans_skipped",
// "points_in", "points_out", "wall_s", "scans_per_second", "stages" (each
// stage's "mean_ms" and "p95_ms"), "metric_map", "semantic_points",
// "segments", "topo_map"}. Costs one pass over the metric map's voxels.
nlohmann::ordered_json run_summary_json(const Mapper& mapper);

// Adds member `key` = `value` to the summary.json in the run folder `folder`
// and commits the folder again: the manifest is rewritten last with
// the same record and every output's new size and hash, so the folder stays
// one set that verify_run_folder accepts. A crash in between leaves the
// folder without a manifest, which readers refuse like any unfinished run.
// Throws sarmap::Error, the folder unchanged, when it does not verify, its
// manifest lists no summary.json, the summary already has `key` (the run's
// own figures are never replaced), or another process is writing it.
void add_to_run_summary(const std::filesystem::path& folder, const std::string& key,
                        const nlohmann::ordered_json& value);

}  // namespace sarmap::pipeline
