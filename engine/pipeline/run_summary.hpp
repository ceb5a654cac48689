// summary.json: a run's headline figures on one page (scans, points, speed,
// per-stage times, map sizes, segment and node counts), taken from the
// Mapper and its profile as they stand; write_run writes it with the other
// outputs (docs/formats.md).
#pragma once

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

}  // namespace sarmap::pipeline
