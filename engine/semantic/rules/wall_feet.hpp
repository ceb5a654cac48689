// Wall feet: floor points at the base of a wall, which the network calls
// wall. Where the floor meets a wall, the floor's last few centimetres and
// the wall's lowest ones lie in the same block and look alike, and the
// network labels some of those floor points wall: all of them at the
// floor's height, within a few centimetres of the wall (how many, and how
// the tolerance was chosen: docs/perf-history.md). A point at the
// floor's height is floor whatever stands next to it, so a point
// labelled wall no higher than `tolerance` above the floor around it becomes
// terrain. The floor around a point is the mean height of the points the
// network labelled terrain in its column and the eight around it (a mean,
// not a lowest point, so that sensor noise does not sink it).
#pragma once

#include <cstddef>

#include "engine/core/point_buffer.hpp"

namespace sarmap {

struct WallFootSettings {
  bool enabled = true;
  double column = 0.1;               // metres, the horizontal grid
  double tolerance = 0.005;          // metres above the floor; below it counts as floor
  std::size_t min_floor_points = 5;  // fewer terrain points around: the floor there is unknown
};

// Throws sarmap::Error (InvalidArgument) for a column under 1 cm, a
// tolerance negative or not finite, or min_floor_points 0.
void validate(const WallFootSettings& settings);

// Relabels as terrain the points labelled wall at the floor's height, as
// above; each such point's "wall" score moves to its "terrain" score when
// both channels exist. Returns how many points changed; nothing when
// disabled or unlabelled. Throws sarmap::Error (InvalidArgument) for
// settings validate() refuses or a non-finite point.
std::size_t label_wall_feet(PointBuffer& points, const WallFootSettings& settings);

}  // namespace sarmap
