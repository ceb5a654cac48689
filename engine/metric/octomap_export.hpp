// Exports the metric map as an OctoMap binary tree (.bt) that OctoMap's own
// readBinary loads: maximum-likelihood occupancy (each known voxel free or
// occupied), pruned (a full subtree of one state is one leaf), in the
// documented layout: header lines, "id OcTree", "size", "res", "data", then
// 2 bytes per inner node in depth-first order. Lives beside the map for the
// same reason as map_file.hpp (io may not depend on metric).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

// The .bt bytes. Throws sarmap::Error (OutOfRange) when a known voxel lies
// outside OctoMap's 16-bit key range (voxel index in [-32768, 32767], i.e.
// +-32768 x resolution metres), naming the axis and the extent.
std::string octomap_binary(const MetricMap& map, std::size_t* node_count = nullptr);
// Writes octomap_binary() atomically.
void write_octomap_bt(const MetricMap& map, const std::filesystem::path& path);

}  // namespace sarmap::metric
