// Small arena descriptions for the sim tests, built as JSON so each test can
// change one key and parse the result.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "engine/sim/arena.hpp"

namespace sarmap::sim::testing {

// A 4 x 4 m floor, no elements, a two-waypoint trajectory, a small
// noise-free depth camera.
inline nlohmann::json base_arena_json() {
  return nlohmann::json::parse(R"({
    "name": "test",
    "bounds": {"min": [0, 0, 0], "max": [4, 4, 2]},
    "floor": true,
    "elements": [],
    "trajectory": {"waypoints": [[0.5, 2], [3.5, 2]], "height": 0.5, "frames": 3, "pitch_deg": -10},
    "sensor": {"type": "depth_camera", "width": 16, "height": 12, "fx": 14, "fy": 14, "cx": 8, "cy": 6,
               "min_range": 0.1, "max_range": 6, "noise": "none"}
  })");
}

inline Arena parse_test_arena(const nlohmann::json& j, const std::string& base_dir = ".") {
  return parse_arena(j.dump(), "test.json", base_dir);
}

// Row-major 16 numbers of a pose.
inline nlohmann::json pose_json(const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) out.push_back(r(i, k));
    out.push_back(t[i]);
  }
  for (double v : {0.0, 0.0, 0.0, 1.0}) out.push_back(v);
  return out;
}

}  // namespace sarmap::sim::testing
