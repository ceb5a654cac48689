// The sensor poses of an arena's trajectory: explicit poses as given, or
// `frames` poses evenly spaced by path length along the waypoints, at
// `height` above the terrain or ramp under the sensor, looking along the
// direction of travel and pitched by pitch_deg (negative looks down).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "engine/core/pose.hpp"
#include "engine/geometry/triangle_scene.hpp"
#include "engine/sim/arena.hpp"

namespace sarmap::sim {

// Rotation of a body (x forward, y left, z up) heading `yaw` (radians from
// +x, counter-clockwise) and pitched by pitch_deg (negative: nose down).
Eigen::Matrix3d body_rotation(double yaw, double pitch_deg);
// Maps a depth camera's optical frame (x right, y down, z forward) to its
// body frame: optical z -> body x, optical x -> body -y, optical y -> body -z.
Eigen::Matrix3d optical_to_body();

std::vector<Pose> trajectory_poses(const Arena& arena, const geometry::TriangleScene& scene);

}  // namespace sarmap::sim
