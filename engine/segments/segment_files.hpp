// The segment map's files: segments.json (every field of every segment, the
// merges that happened) and segments.ply (each rectangle as a quad in its
// class colour, for MeshLab, CloudCompare or Open3D). Written atomically.
//
// segments.json: {"version": 1, "segments": [{"id", "class", "class_id",
//   "normal": [x, y, z], "offset", "centroid": [x, y, z], "slope_deg",
//   "area_m2", "inliers", "thickness", "rectangle": {"center": [x, y, z],
//   "axes": [[...], [...]], "half_extents": [a, b]}, "min": [...], "max": [...]}],
//   "merges": [[absorbed id, surviving id], ...]}
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "engine/segments/segment.hpp"
#include "engine/segments/segment_map.hpp"

namespace sarmap::segments {

inline constexpr int kSegmentsFormatVersion = 1;

struct SegmentsFile {
  std::vector<Segment> segments;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> merges;
};

std::string segments_json(const SegmentMap& map);
void write_segments_json(const std::filesystem::path& path, const SegmentMap& map);
void write_segments_ply(const std::filesystem::path& path, const SegmentMap& map);
// Throws sarmap::Error (Io, Parse, InvalidData) naming the file, the
// segment's index and the key that is wrong.
SegmentsFile read_segments_json(const std::filesystem::path& path);

}  // namespace sarmap::segments
