// One PLY or PCD file seen as a one-scan sequence: identity pose, sensor at
// the origin. Lets every command that takes a sequence also take a cloud.
#pragma once

#include <filesystem>
#include <memory>

#include "engine/io/scan_source.hpp"

namespace sarmap {

// Throws sarmap::Error when the file does not exist or is not .ply / .pcd.
std::unique_ptr<ScanSource> open_single_cloud(const std::filesystem::path& path, const InputLimits& limits = {});

}  // namespace sarmap
