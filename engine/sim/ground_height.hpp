// Height of the terrain or ramp under a point of an arena's scene, looking
// through walls and obstacles: where the simulated robot's wheels stand.
#pragma once

#include "engine/geometry/triangle_scene.hpp"

namespace sarmap::sim {

// Height of the highest terrain or ramp surface under (x, y) below z_top;
// 0 when there is none.
double ground_height(const geometry::TriangleScene& scene, double x, double y, double z_top);

}  // namespace sarmap::sim
