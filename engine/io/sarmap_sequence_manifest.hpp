// sequence.json, the index of sarmap's own sequence folder, in both
// directions: parsed with every field checked, and written back. Format:
//   {"version": 1, "points_frame": "world" | "sensor",
//    "sensor": {"type": "depth_camera" | "lidar", "max_range": m, "min_range": m,
//               "width", "height", "fx", "fy", "cx", "cy"},        (optional)
//    "arena_sha256": "64 lowercase hex digits",                    (optional: simulated sequences)
//    "frames": [{"file": "frame_000000.ply", "pose": [16 row-major numbers],
//                "origin": [x, y, z], "timestamp": s}, ...]}      (origin, timestamp optional;
//   timestamps are given for every frame or for none, and never decrease)
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "engine/core/pose.hpp"
#include "engine/core/sensor_info.hpp"

namespace sarmap {

inline constexpr int kSequenceFormatVersion = 1;

enum class PointsFrame { World, Sensor };

struct SequenceManifestFrame {
  std::string file;  // as written: relative to the folder, or absolute
  Pose pose;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // defaults to the pose's translation
  double timestamp = 0.0;
};

struct SequenceManifest {
  PointsFrame points_frame = PointsFrame::World;
  SensorInfo sensor;
  std::vector<SequenceManifestFrame> frames;
  // SHA-256 of the arena description a simulated sequence was rendered from
  // (the arena file's bytes), so a run can name the arena that scores it;
  // empty for recordings and for sequences written before it was recorded.
  std::string arena_sha256;
};

// Parses and validates; `file` names the source in errors, e.g.
// "seq/sequence.json: frames[3].pose: expected 16 numbers, got 12".
// Unknown keys, a version other than 1, a pose that is not a rotation, a
// timestamp earlier than the previous frame's are all errors.
SequenceManifest parse_sequence_manifest(std::string_view json_text, const std::string& file);
SequenceManifest read_sequence_manifest(const std::filesystem::path& path);

// The JSON text of a manifest (what SequenceWriter writes).
std::string sequence_manifest_json(const SequenceManifest& manifest);

std::string_view to_string(PointsFrame frame);

}  // namespace sarmap
