// The arena description (datasets/arenas/*.json) as plain structs, and its
// strict parser: every unknown key, missing key or out-of-range value is an
// error naming the file, the element index and the key.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/core/pose.hpp"
#include "engine/core/sensor_info.hpp"

namespace sarmap::sim {

// A vertical box centred on the segment from..to, standing on the floor.
struct WallSpec {
  Eigen::Vector2d from, to;
  double height = 0, thickness = 0;
};

// A wedge on the floor rising towards its local +x at angle_deg; its high end
// is length * tan(angle) tall with a vertical back face.
struct InclinedRampSpec {
  Eigen::Vector2d center;
  double length = 0, width = 0, angle_deg = 0, yaw_deg = 0;
};

// A box-shaped platform standing on the floor, top at `height`.
struct FlatRampSpec {
  Eigen::Vector2d center;
  Eigen::Vector2d size;
  double height = 0, yaw_deg = 0;
};

// Any box obstacle, anywhere.
struct BoxSpec {
  Eigen::Vector3d center;
  Eigen::Vector3d size;
  double yaw_deg = 0;
};

// Triangles loaded from a file (OBJ, STL, DAE) with its node transforms
// applied, then scaled, rotated (R = Rz(yaw) Ry(pitch) Rx(roll)) and moved.
struct MeshSpec {
  std::filesystem::path path;  // resolved against the arena file's folder
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  // The file's triangles in its own frame (node transforms applied), loaded
  // while parsing so a broken file is reported with the element's index.
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::uint32_t> indices;  // three per triangle
};

struct ArenaElement {
  std::variant<WallSpec, InclinedRampSpec, FlatRampSpec, BoxSpec, MeshSpec> shape;
  ClassId label = ClassId::Other;  // class of every face of the element
};

// "wall", "inclined_ramp", "flat_ramp", "box" or "mesh".
std::string_view element_type_name(const ArenaElement& element);

// A waypoint trajectory's frame count is at most this (an hour at 30 Hz).
inline constexpr std::size_t kMaxTrajectoryFrames = 108'000;

struct TrajectorySpec {
  // Either waypoints (xy) driven at `height` above the surface under them...
  std::vector<Eigen::Vector2d> waypoints;
  double height = 0;
  std::size_t frames = 0;
  double pitch_deg = 0;
  // ...or explicit sensor-to-world poses (then waypoints is empty).
  std::vector<Pose> poses;
};

enum class NoiseKind { None, Gaussian, Kinect };

struct NoiseSpec {
  NoiseKind kind = NoiseKind::None;
  double sigma = 0;    // Gaussian only (metres)
  double dropout = 0;  // fraction of returns lost, in [0, 1)
};

struct SensorSpec {
  SensorType type = SensorType::DepthCamera;
  PinholeIntrinsics intrinsics;  // depth camera
  int rings = 0;                 // LiDAR
  int horizontal_samples = 0;    // LiDAR
  double vertical_fov_min_deg = 0, vertical_fov_max_deg = 0;  // LiDAR
  double min_range = 0, max_range = 0;
  NoiseSpec noise;
};

struct Arena {
  std::string name;
  Eigen::Vector3d bounds_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d bounds_max = Eigen::Vector3d::Zero();
  bool floor = true;
  std::vector<ArenaElement> elements;
  TrajectorySpec trajectory;
  SensorSpec sensor;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> eval_pairs;
  // Where the description came from, for messages.
  std::string source;
  // SHA-256 of the description's bytes as parsed (load_arena: the file's
  // bytes). A simulated sequence records it, so a run's arena can be checked
  // (eval::evaluate_run). Empty for an arena built in code; a mesh element's
  // file is not part of it.
  std::string sha256;
};

// Parses a description; `source` names it in errors, mesh paths are resolved
// against `base_dir`. Throws sarmap::Error(Parse / InvalidData / Io).
Arena parse_arena(std::string_view json_text, std::string_view source,
                  const std::filesystem::path& base_dir);
// Reads and parses a file (meshes relative to its folder).
Arena load_arena(const std::filesystem::path& path);

// The sensor as the sequence format records it.
SensorInfo sensor_info(const SensorSpec& sensor);

}  // namespace sarmap::sim
