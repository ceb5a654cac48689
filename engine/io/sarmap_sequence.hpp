// sarmap's own sequence folder read as a stream: sequence.json (see
// sarmap_sequence_manifest.hpp) plus one PLY or PCD file per frame, read only
// when its frame is reached.
#pragma once

#include <filesystem>
#include <memory>

#include "engine/io/scan_source.hpp"

namespace sarmap {

// Reads and checks sequence.json and that every frame file exists; the
// points are read frame by frame in next(). Sensor-frame points are moved
// into the world by their pose; a label outside the class table is an error.
std::unique_ptr<ScanSource> open_sarmap_sequence(const std::filesystem::path& folder,
                                                 const InputLimits& limits = {});

}  // namespace sarmap
