// sarmap's own metric-map file (.sarmap), little-endian binary:
//   "SARMAPVX" | u32 version (3) | f64 resolution | u8 fusion | u8 payload layout (3)
//   | u16 payload bytes (7) | f64 x 8 settings (prob_hit, prob_miss, clamp_min,
//   clamp_max, occupied_threshold, label_confidence, evidence_clamp,
//   free_evidence_keep) | u64 block count
//   | per block, in (z, y, x) order: i32 x, y, z, u8 occupancy (0: one i8
//     log-odds for all 512 voxels, 1: 512 x i8; -128 is unknown), u64 x 8
//     evidence mask (bit l: voxel l holds evidence), then i8 evidence[6] per
//     voxel whose bit is set, in voxel order (voxel index x + 8y + 64z)
//   | u32 CRC-32 (zlib) of every byte before it.
// Log-odds are in 1/32 nat, Bayesian evidence in 1/6 nat (semantic_voxel.hpp,
// label_fusion.hpp). Version 2 (layout 2) was the same with i16 values in
// 1/1024 nat and 1/256 nat; version 1 (layout 1) stored every voxel as i16
// log_odds + i16 evidence[6]. load_map still reads both, converting their
// values to today's units. docs/formats.md has all three.
// The format lives in engine/metric rather than engine/io because it is the
// map's own layout and io may not depend on metric (docs/architecture.md);
// it writes through io's AtomicFileWriter.
#pragma once

#include <cstdint>
#include <filesystem>

#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

// The version save_map writes; load_map reads it and every earlier one.
inline constexpr std::uint32_t kMapFileVersion = 3;

// True for a path whose extension is .sarmap (any case): what `sarmap info`
// and `sarmap convert` open as a metric map rather than a point cloud.
bool is_map_file_path(const std::filesystem::path& path);

// Written atomically: a crash leaves the old file or none, never half a map.
// The bytes depend only on the map's voxels and settings, not on how its
// storage grew (a resumed run writes the same file as an uninterrupted one).
void save_map(const MetricMap& map, const std::filesystem::path& path);
// Loads the whole file or throws sarmap::Error naming the file, the byte
// offset and what is wrong (Io, Parse); never returns a partly loaded map.
MetricMap load_map(const std::filesystem::path& path);

// load_map, with the format version the file was written in (what
// `sarmap info` reports).
struct MapFile {
  MetricMap map;
  std::uint32_t version;
};
MapFile read_map_file(const std::filesystem::path& path);

}  // namespace sarmap::metric
