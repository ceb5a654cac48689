// A check of the network's inclined-ramp labels against the surface they lie
// on. The DGCNN sees one block at a time (the model's block size, from its
// metadata); with the camera pitched down and walls at the edge of its
// range, only a wall's lowest band is in view and the network can take that
// band for a ramp (most of all in the held-out arenas with the steepest
// camera, 9002 and 9005). The arenas' inclined ramps are 10-25
// degrees, so a surface fitted over a neighbourhood wider than a block's
// detail and steeper than min_slope_deg cannot be one: such points become
// wall, or other where the network scored other above wall.
#pragma once

#include <cstddef>

#include "engine/core/point_buffer.hpp"

namespace sarmap {

struct SteepSurfaceVetoSettings {
  bool enabled = true;
  double cell = 0.2;            // metres; the surface is fitted over 3 x 3 x 3 cells
  double min_slope_deg = 60.0;  // surfaces at least this steep carry no inclined ramp
  std::size_t min_points = 10;  // fewer points around: no verdict, the label stays
};

// Throws sarmap::Error (InvalidArgument) for a cell under 1 cm or a slope
// outside (0, 90].
void validate(const SteepSurfaceVetoSettings& settings);

// Relabels the points labelled inclined ramp whose surface is at least
// min_slope_deg steep (z up), as above; the choice between wall and other
// uses the score channels named "wall" and "other" when both exist, else
// wall, and the point's "inclined_ramp" score moves to the class it becomes
// (so the label stays the scores' arg-max and the map's score fusion agrees).
// Returns how many points changed. Throws sarmap::Error
// (InvalidArgument) for settings validate() refuses and (like the normals)
// for a non-finite point.
std::size_t veto_steep_inclined_ramps(PointBuffer& points, const SteepSurfaceVetoSettings& settings);

}  // namespace sarmap
