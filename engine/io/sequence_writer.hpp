// Writes sarmap's own sequence folder: one binary PLY per frame
// (frame_000000.ply, ...) and sequence.json, written last and atomically so a
// reader never sees a sequence that names frames which are not there.
//
// sequence.json: {"version": 1, "points_frame": "world" | "sensor",
//   "sensor": {"type": ..., "max_range": ..., ...intrinsics},
//   "arena_sha256": "..." (a simulated sequence's arena),
//   "frames": [{"file", "pose": [16 row-major], "origin": [x,y,z], "timestamp"}]}
// (format and checks: sarmap_sequence_manifest.hpp)
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "engine/core/scan.hpp"
#include "engine/core/sensor_info.hpp"
#include "engine/io/sarmap_sequence_manifest.hpp"

namespace sarmap {

class SequenceWriter {
 public:
  // Creates the folder if needed and removes a sequence.json already there,
  // so the old index never names frames being overwritten. Throws
  // InvalidArgument for a sensor the reader would refuse (intrinsics without
  // an image size, range or intrinsics without a sensor type, ...).
  SequenceWriter(std::filesystem::path folder, SensorInfo sensor);
  // Writes the scan's points (world frame) as the next frame and records its
  // pose, origin, timestamp. Timestamps must not decrease.
  void add(const Scan& scan);
  // Records the SHA-256 of the arena file a simulated sequence comes from
  // (64 lowercase hex digits; InvalidArgument otherwise), so that runs of it
  // name their arena and eval can refuse another. Before finish().
  void set_arena_sha256(std::string sha256);
  // Writes sequence.json. Nothing names the frames until this is called.
  void finish();
  std::size_t frames_written() const { return manifest_.frames.size(); }
  const std::filesystem::path& folder() const { return folder_; }

 private:
  std::filesystem::path folder_;
  SequenceManifest manifest_;
  bool finished_ = false;
};

// Removes from `folder` what a SequenceWriter writes there, so a shorter
// sequence written after a longer one leaves no stale frames: sequence.json
// first (no index then names a missing frame), every regular file named
// frame_NNNNNN.ply (six or more digits) directly in it, and the temporaries
// of writers that were killed. Every other file and subfolder stays. A folder
// that does not exist is left so. Throws sarmap::Error naming a file that
// cannot be removed.
void remove_written_sequence(const std::filesystem::path& folder);

}  // namespace sarmap
