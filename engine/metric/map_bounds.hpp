// Keeping a long mission's map bounded: drop the blocks beyond a radius of
// the robot, or the farthest blocks once the map holds more than a budget.
// What is dropped becomes unknown again, exactly as if never observed.
#pragma once

#include <cstddef>

#include <Eigen/Core>

#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

struct MapBounds {
  // Blocks whose centre lies farther than this (metres) from the sensor are
  // dropped after every scan; 0 keeps every distance.
  double keep_radius = 0.0;
  // At most this many blocks (8^3 voxels each) are kept, the farthest from
  // the sensor dropped first; 0 keeps any number.
  std::size_t max_blocks = 0;

  bool limited() const { return keep_radius > 0.0 || max_blocks > 0; }
};

// Throws sarmap::Error (InvalidArgument) for a negative or non-finite radius.
void validate(const MapBounds& bounds);

// Drops every block whose centre is farther than radius (metres) from centre.
// Returns how many were dropped.
std::size_t drop_blocks_beyond(MetricMap& map, const Eigen::Vector3d& centre, double radius);

// Drops the blocks farthest from centre (by block centre; equal distances by
// block key, so the result does not depend on hash order) until at most
// max_blocks remain. Returns how many were dropped.
std::size_t drop_farthest_blocks(MetricMap& map, const Eigen::Vector3d& centre, std::size_t max_blocks);

// Both, as the settings ask (the radius first). Returns the blocks dropped.
std::size_t apply_bounds(MetricMap& map, const Eigen::Vector3d& centre, const MapBounds& bounds);

}  // namespace sarmap::metric
