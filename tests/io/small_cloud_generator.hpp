// Builds the labelled cloud shipped as datasets/fixtures/small_cloud.ply: a
// floor (terrain), a wall and an inclined ramp, with seeded noise, so the
// fixture can be regenerated bit for bit and checked against its source.
#pragma once

#include "engine/core/point_buffer.hpp"

namespace sarmap::test {

// About 3300 points with colours (the class colours) and labels 1, 2, 3.
PointBuffer make_small_arena_cloud();

}  // namespace sarmap::test
