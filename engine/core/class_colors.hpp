// Colours points by their class from the one class table (classes.hpp), so
// every file that shows classes as colour (voxels.ply, semantic_points.ply)
// uses the same palette as the segment and graph files.
#pragma once

#include "engine/core/point_buffer.hpp"

namespace sarmap {

// Sets each point's red, green and blue to its label's class colour (a label
// that is no class id gets the unknown class's colour), enabling colours if
// needed. Throws sarmap::Error (InvalidArgument) when the points have no labels.
void paint_class_colors(PointBuffer& points);

}  // namespace sarmap
