// The shipped default arena, loaded once per test binary: what the
// pipeline's tests map.
#pragma once

#include <string>

#include "engine/sim/arena.hpp"

namespace sarmap::testing {

inline const sim::Arena& default_arena() {
  static const sim::Arena arena =
      sim::load_arena(std::string(SARMAP_SOURCE_DIR) + "/datasets/arenas/esogu-6x4.json");
  return arena;
}

}  // namespace sarmap::testing
