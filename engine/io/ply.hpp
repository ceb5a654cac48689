// PLY point clouds: ASCII and binary little-endian, read and write.
// Properties: x y z (float or double), red green blue (uchar), label and
// gt_label (class id), nx ny nz, intensity, scalar_<name> (float). Unknown
// properties and other elements (faces) are skipped, not fatal.
#pragma once

#include <filesystem>

#include "engine/core/point_buffer.hpp"
#include "engine/io/point_cloud_file.hpp"

namespace sarmap {

PointBuffer read_ply(const std::filesystem::path& path, PointCloudFileInfo* info = nullptr,
                     const InputLimits& limits = {});
void write_ply(const std::filesystem::path& path, const PointBuffer& points,
               const PointCloudWriteOptions& options = {});

}  // namespace sarmap
