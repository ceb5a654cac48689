// A small sensor-frame sequence folder written from PLY texts, for the CLI
// tests of bad frames: frame k is `<a + k>.ply` at its pose, behind a
// sequence.json of a 10 m LiDAR.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tests/io/scratch_folder.hpp"

namespace sarmap::test {

inline constexpr const char* kIdentityPose = "[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]";

struct SequenceFrame {
  std::string ply;                   // the frame file's text
  std::string pose = kIdentityPose;  // a row-major 4 x 4 JSON array
};

// Writes the sequence into dir/name and returns that folder.
inline std::filesystem::path write_frame_sequence(const ScratchFolder& dir, const std::string& name,
                                                  const std::vector<SequenceFrame>& frames) {
  std::string listed;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::string file = std::string(1, static_cast<char>('a' + k)) + ".ply";
    dir.write(name + "/" + file, frames[k].ply);
    listed += std::string(k == 0 ? "" : ", ") + R"({"file": ")" + file + R"(", "pose": )" + frames[k].pose + "}";
  }
  dir.write(name + "/sequence.json",
            R"({"version": 1, "points_frame": "sensor", "sensor": {"type": "lidar", "max_range": 10}, "frames": [)" +
                listed + "]}");
  return dir / name;
}

}  // namespace sarmap::test
