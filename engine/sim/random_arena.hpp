// Procedurally generated NIST-like arenas for training data: outer walls,
// interior walls with doorways forming rooms (and a corridor), 1-4 inclined
// ramps (10-25 degrees), 1-3 flat ramps (0.1-0.4 m), a few obstacles, random
// yaws, and a trajectory planned on a grid that visits every ramp and looks
// at it. The seed goes into the name, so no two seeds give the same arena.
#pragma once

#include <cstdint>
#include <string>

#include "engine/sim/arena.hpp"

namespace sarmap::sim {

// The generated description as JSON text (what --write-arena saves).
std::string random_arena_json(std::uint64_t seed);
// The same, parsed.
Arena random_arena(std::uint64_t seed);

}  // namespace sarmap::sim
