// Exports the metric map as an OctoMap ColorOcTree (.ot, OctoMap's full tree
// format) that AbstractOcTree::read loads and octovis shows in class colours:
// every known voxel with its own occupancy log-odds (not only free/occupied,
// as map.bt), occupied voxels in their class colour (engine/core/classes.hpp),
// free voxels with OctoMap's "no colour" white. Written here, without
// liboctomap, for the same reason as octomap_export.hpp. Layout in
// docs/formats.md.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

// The .ot bytes. Throws sarmap::Error (OutOfRange) when a known voxel lies
// outside OctoMap's 16-bit key range, as octomap_binary() does.
std::string octomap_color_tree(const MetricMap& map, std::size_t* node_count = nullptr);
// Writes octomap_color_tree() atomically.
void write_octomap_ot(const MetricMap& map, const std::filesystem::path& path);

}  // namespace sarmap::metric
