// Files that ship in the source tree and that commands use by default: the
// built-in default arena and the trained ramp model.
#pragma once

#include <filesystem>

namespace sarmap::cli {

// datasets/arenas/esogu-6x4.json
std::filesystem::path shipped_default_arena();
// datasets/models/ramps-dgcnn.safetensors: `run --classifier dgcnn` without --model.
std::filesystem::path shipped_ramp_model();

}  // namespace sarmap::cli
