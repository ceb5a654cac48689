// The CLI tests' smallest arena: a few walls and a ramp, mapped in seconds.
#pragma once

#include <string>

namespace sarmap::testing {

inline const std::string kTinyArena = SARMAP_SOURCE_DIR "/tests/cli/data/tiny_arena.json";

}  // namespace sarmap::testing
