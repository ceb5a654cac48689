// sarmap's own metric-map file (.sarmap), little-endian binary:
//   "SARMAPVX" | u32 version (1) | f64 resolution | u8 fusion | u8 payload layout (1)
//   | u16 payload bytes (14) | f64 x 8 settings (prob_hit, prob_miss, clamp_min,
//   clamp_max, occupied_threshold, label_confidence, evidence_clamp,
//   free_evidence_keep) | u64 block count
//   | per block, in (z, y, x) order: i32 x, y, z, then 512 voxels of
//     i16 log_odds + i16 evidence[6] (voxel index x + 8y + 64z)
//   | u32 CRC-32 (zlib) of every byte before it.
// The format lives in engine/metric rather than engine/io because it is the
// map's own layout and io may not depend on metric (docs/architecture.md);
// it writes through io's AtomicFileWriter.
#pragma once

#include <cstdint>
#include <filesystem>

#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

inline constexpr std::uint32_t kMapFileVersion = 1;

// True for a path whose extension is .sarmap (any case): what `sarmap info`
// and `sarmap convert` open as a metric map rather than a point cloud.
bool is_map_file_path(const std::filesystem::path& path);

// Written atomically: a crash leaves the old file or none, never half a map.
void save_map(const MetricMap& map, const std::filesystem::path& path);
// Loads the whole file or throws sarmap::Error naming the file, the byte
// offset and what is wrong (Io, Parse); never returns a partly loaded map.
MetricMap load_map(const std::filesystem::path& path);

}  // namespace sarmap::metric
