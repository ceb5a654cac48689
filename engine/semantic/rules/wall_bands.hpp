// Wall bands, which the network calls other. With the camera pitched down,
// far walls show only their lowest band, a few tens of centimetres high,
// and one block's view of that band looks like the side of a box (most of
// all in the held-out arenas with the steepest camera, 9002 and 9005). The
// arenas' boxes are at most 0.6 m a side; a wall band runs on for metres.
// So the columns of a horizontal grid that hold points labelled other or
// wall are grouped into patches (neighbouring columns), and in a patch at
// least min_length long along its principal
// axis the points labelled other are wall. Wall-labelled columns count
// towards the length because the network often splits one band into
// stretches of wall and of other, each shorter than a box; a box's sides,
// labelled wall or other, stay one box-sized patch.
#pragma once

#include <cstddef>

#include "engine/core/point_buffer.hpp"

namespace sarmap {

struct WallBandSettings {
  bool enabled = true;
  double column = 0.1;      // metres, the horizontal grid
  // Metres; patches at least this long are wall. Under the boxes' 0.85 m
  // diagonal, so a box set at 45 degrees to the grid can pass for wall:
  // measured, 0.8 m gains more wall than it loses boxes (docs/perf-history.md).
  double min_length = 0.8;
};

// Throws sarmap::Error (InvalidArgument) for a column under 1 cm or a
// length not positive.
void validate(const WallBandSettings& settings);

// Relabels as wall the points labelled other in patches (of columns
// holding other or wall) at least min_length long, as above; each such
// point's "other" score moves to its
// "wall" score when both channels exist. Returns how many points changed;
// nothing when disabled or unlabelled. Throws sarmap::Error
// (InvalidArgument) for settings validate() refuses or a non-finite point.
std::size_t label_wall_bands(PointBuffer& points, const WallBandSettings& settings);

}  // namespace sarmap
