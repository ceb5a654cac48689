// Procedurally generated NIST-like arenas for training data: outer walls,
// interior walls with doorways forming rooms (and a corridor), 1-4 inclined
// ramps (10-25 degrees), 1-3 flat ramps (0.1-0.4 m), a few obstacles, random
// yaws, and a trajectory planned on a grid that visits every ramp and looks
// at it. The seed goes into the name, so no two seeds give the same arena.
// The sensor is a depth camera unless a RandomSensor asks for a LiDAR; the
// sensor never changes the layout or the trajectory's path.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "engine/sim/arena.hpp"

namespace sarmap::sim {

// The sensor a random arena is seen with. The defaults are the depth camera
// every random arena had before the choice existed (its JSON is unchanged).
// Values are not checked here; the arena parser refuses bad ones.
struct RandomSensor {
  SensorType type = SensorType::DepthCamera;
  // Above the ground under the robot (m); unset: 0.5.
  std::optional<double> height;
  // Nose up is positive (degrees); unset: the depth camera's is drawn from
  // the seed in [-25, -10], the LiDAR's is 0.
  std::optional<double> pitch_deg;
  // Unset: 0.3-5 m for the depth camera, 0.4-12 m for the LiDAR.
  std::optional<double> min_range, max_range;
  // Depth camera (Kinect-like noise): image size; the focal length scales
  // with the width, keeping the 60-degree horizontal field of view of
  // 320 x 240 at fx = fy = 277.
  int width = 320, image_height = 240;
  // LiDAR (Gaussian range noise, sigma 1 cm): rings evenly spread over the
  // vertical field of view, samples per ring over 360 degrees (VLP-16-like
  // defaults).
  int rings = 16, samples = 1800;
  double vertical_fov_min_deg = -15, vertical_fov_max_deg = 15;
};

// The generated description as JSON text (what --write-arena saves).
std::string random_arena_json(std::uint64_t seed, const RandomSensor& sensor = {});
// The same, parsed.
Arena random_arena(std::uint64_t seed, const RandomSensor& sensor = {});

}  // namespace sarmap::sim
