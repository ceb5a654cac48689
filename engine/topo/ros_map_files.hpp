// A PlanningGrid as the two files ROS map_server loads (and map_saver writes):
// an 8-bit binary PGM, top row = highest y, and a YAML file naming it with
// the resolution, the origin and the trinary thresholds. Written atomically;
// read back for round trips and for tools that take a saved map.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "engine/topo/planning_grid.hpp"

namespace sarmap::topo {

// map_saver's pixel values. With negate 0 map_server reads a pixel as
// occupied with probability (255 - v) / 255: 0 -> 1.0 (occupied), 254 ->
// 0.004 (free), 205 -> 0.196, just above free_thresh, so neither: unknown.
inline constexpr std::uint8_t kRosFreePixel = 254;
inline constexpr std::uint8_t kRosOccupiedPixel = 0;
inline constexpr std::uint8_t kRosUnknownPixel = 205;
inline constexpr double kRosOccupiedThreshold = 0.65;
inline constexpr double kRosFreeThreshold = 0.196;

struct RosMapPaths {
  std::filesystem::path image;  // <folder>/<stem>.pgm
  std::filesystem::path yaml;   // <folder>/<stem>.yaml
};

// Writes the image first, then the YAML that names it (by its file name,
// which map_server resolves beside the YAML), so a reader that finds the YAML
// also finds its image. The folder must exist. stem: letters, digits, '.',
// '_' and '-' only, so the YAML needs no quoting. Throws sarmap::Error
// (InvalidArgument for a bad stem, Io when a file cannot be written).
RosMapPaths write_ros_map(const PlanningGrid& grid, const std::filesystem::path& folder,
                          std::string_view stem = "grid");

// The YAML text write_ros_map writes, e.g.
//   image: grid.pgm\nresolution: 0.05\norigin: [-2.5, 1.0, 0.0]\nnegate: 0\n
//   occupied_thresh: 0.65\nfree_thresh: 0.196\n
// Numbers are the shortest text that reads back to the same double.
std::string ros_map_yaml(const PlanningGrid& grid, std::string_view image_name);

// Reads a map_server YAML and the PGM it names (relative to the YAML's
// folder unless absolute), classifying pixels as map_server does in trinary
// mode with the file's negate and thresholds. Accepts comments, quoted
// values, unknown keys (ignored) and PGM header comments; refuses a rotated
// origin, a mode other than trinary and PGMs that are not 8-bit binary
// (Unsupported), and anything malformed (Parse, naming the file and line or
// byte offset). Io when a file cannot be read.
PlanningGrid read_ros_map(const std::filesystem::path& yaml_path);

}  // namespace sarmap::topo
