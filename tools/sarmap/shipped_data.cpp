#include "tools/sarmap/shipped_data.hpp"

namespace sarmap::cli {

namespace {

// The source tree the binary was built from (set by CMake).
std::filesystem::path datasets_dir() { return std::filesystem::path(SARMAP_SOURCE_DIR) / "datasets"; }

}  // namespace

std::filesystem::path shipped_default_arena() { return datasets_dir() / "arenas" / "esogu-6x4.json"; }

std::filesystem::path shipped_ramp_model() { return datasets_dir() / "models" / "ramps-dgcnn.safetensors"; }

}  // namespace sarmap::cli
