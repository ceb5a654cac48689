// Writes sarmap's own sequence folder: one binary PLY per frame
// (frame_000000.ply, ...) and sequence.json, written last and atomically so a
// reader never sees a sequence that names frames which are not there.
//
// sequence.json: {"version": 1, "points_frame": "world" | "sensor",
//   "sensor": {"type": ..., "max_range": ..., ...intrinsics},
//   "frames": [{"file", "pose": [16 row-major], "origin": [x,y,z], "timestamp"}]}
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include "engine/core/scan.hpp"
#include "engine/core/sensor_info.hpp"

namespace sarmap {

inline constexpr int kSequenceFormatVersion = 1;

class SequenceWriter {
 public:
  // Creates the folder if needed. Points are written in the world frame.
  SequenceWriter(std::filesystem::path folder, SensorInfo sensor);
  // Writes the scan's points as the next frame and records its pose, origin, timestamp.
  void add(const Scan& scan);
  // Writes sequence.json. Nothing names the frames until this is called.
  void finish();
  std::size_t frames_written() const { return frames_.size(); }

 private:
  struct FrameRecord {
    std::string file;
    Eigen::Matrix4d pose;
    Eigen::Vector3d origin;
    double timestamp;
  };
  std::filesystem::path folder_;
  SensorInfo sensor_;
  std::vector<FrameRecord> frames_;
};

}  // namespace sarmap
