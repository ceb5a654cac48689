// What the ground along a straight drive says about it, read off the
// traversability grid's surface heights: whether the ground is known all the
// way, whether it drops by more than a step anywhere or comes within the
// robot's radius of such a drop (a platform's edge with no ramp, a ramp's
// side), how steep it climbs, and what class it mostly is.
#pragma once

#include <cstdint>
#include <string_view>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/topo/topo_settings.hpp"
#include "engine/topo/traversability_grid.hpp"

namespace sarmap::topo {

// Why a drive fails, in order of precedence.
enum class DriveVerdict : std::uint8_t { Passes, Wall, Drop, Steep, Unknown };

std::string_view to_string(DriveVerdict verdict);

struct GroundProfile {
  DriveVerdict verdict = DriveVerdict::Passes;  // Passes, Drop, Steep or Unknown (walls are the scene's)
  double slope_deg = 0;                          // between the two stand points
  ClassId ground = ClassId::Unknown;             // the class most samples stand on
};

// Samples the grid every half cell from `from` to `to` (stand points on the
// ground). Steepness is judged over stretches of at least half a metre, less
// one voxel for the heights' quantisation.
GroundProfile ground_profile(const TraversabilityGrid& grid, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                             const TopoSettings& settings);

}  // namespace sarmap::topo
