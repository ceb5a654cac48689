// A scan sequence read as a stream: one scan in memory at a time. Opened by
// open_scan_sequence(), which recognises sarmap's own sequence folder
// (sequence.json), the TUM RGB-D layout and the 7-Scenes layout.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "engine/core/scan.hpp"
#include "engine/core/sensor_info.hpp"
#include "engine/io/input_limits.hpp"

namespace sarmap {

class ScanSource {
 public:
  virtual ~ScanSource() = default;
  // Number of frames in the sequence.
  virtual std::size_t size() const = 0;
  // Reads the next scan into `scan` (points in the world frame); false at the
  // end. Throws sarmap::Error naming the frame's file when the frame cannot be
  // read; the source has then moved past it, so a caller may go on.
  virtual bool next(Scan& scan) = 0;
  // Restarts from the first frame.
  virtual void rewind() = 0;
  // Makes `frame` the next frame read (a resumed run): indexed sequences
  // jump there, without reading the frames before it.
  virtual void skip_to(std::size_t frame) = 0;
  virtual const SensorInfo& sensor() const = 0;
  // "sarmap", "tum", "7scenes" or "cloud" (a single PLY/PCD file as one scan).
  virtual std::string layout() const = 0;
  // Frames of the dataset left out of the sequence (a TUM depth frame with no
  // ground-truth pose close enough in time); size() does not count them.
  virtual std::size_t skipped_frames() const { return 0; }
  // The SHA-256 of the arena description a simulated sequence was rendered
  // from (sequence.json's "arena_sha256"); empty for recorded data and for
  // sequences that do not record it.
  virtual std::string arena_sha256() const { return {}; }
};

struct ScanSequenceOptions {
  // Pinhole intrinsics for depth-image layouts: a JSON file
  // {"fx":..,"fy":..,"cx":..,"cy":.., "width":.., "height":..} or a text 3x3 matrix.
  std::optional<std::filesystem::path> intrinsics_file;
  // Depth values larger than this are dropped for depth images (0 = keep all).
  double max_depth = 0.0;
  // TUM RGB-D: a depth frame takes the ground-truth pose nearest in time and
  // is skipped when that pose is farther than this (seconds).
  double max_time_difference = 0.02;
  // Size of each frame's file and points per frame, checked before reading it.
  InputLimits limits;
};

// Opens a folder in one of the known layouts, or a single PLY/PCD file as a
// one-scan sequence with an identity pose. Throws sarmap::Error naming what
// is missing when the layout is not recognised.
std::unique_ptr<ScanSource> open_scan_sequence(const std::filesystem::path& path,
                                               const ScanSequenceOptions& options = {});

}  // namespace sarmap
