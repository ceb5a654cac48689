// Settings of the topological map and its planners: the robot's size, what it
// can climb, how densely nodes are placed and how far edges reach. One
// default each, documented here once.
#pragma once

#include <vector>

namespace sarmap::topo {

struct TopoSettings {
  // Clearance kept from walls and obstacles (the robot's radius), metres.
  double robot_radius = 0.2;
  // Space above the ground that must be free of obstacles for the robot, metres.
  double robot_height = 0.5;
  // Heights above the ground (metres) at which an edge is tested against the
  // wall scene: the robot's body, from its bumper up.
  std::vector<double> body_heights{0.1, 0.3};
  // Steepest ground an edge may climb, degrees from horizontal.
  double max_slope_deg = 25.0;
  // Largest change of ground height between neighbouring places (a step the
  // robot drives over), metres; more is a drop, such as a platform's edge
  // where no ramp leads down.
  double max_step = 0.08;
  // Nodes on terrain and platform tops stand on a lattice of this pitch
  // (metres), so they are at least this far apart and never move.
  double node_spacing = 0.75;
  // Candidate edges join nodes at most this far apart, metres.
  double edge_radius = 1.6;
  // Occupied voxels of class wall or other are walls too (beside the wall segments).
  bool obstacle_voxels = true;
  // Whether edges and grid paths may cross ground nobody has seen.
  bool unknown_traversable = false;
};

// Throws sarmap::Error (InvalidArgument) naming the first setting out of range.
void validate(const TopoSettings& settings);

}  // namespace sarmap::topo
