// PCD v0.7 point clouds: read ascii, binary and binary_compressed (LZF);
// write ascii and binary (binary_compressed with options.compressed). Fields
// x y z, rgb (U 4, packed 0x00RRGGBB; F 4 read as bits), label, and optionally
// gt_label, normal_x/y/z, intensity, scalar_<name>. Unknown fields and
// COUNT > 1 fields are skipped; WIDTH * HEIGHT must equal POINTS. Zero bytes
// after binary points are padding (PCL 1.13 writes them), any other an error;
// bytes after a binary_compressed block are not read.
#pragma once

#include <filesystem>

#include "engine/core/point_buffer.hpp"
#include "engine/io/point_cloud_file.hpp"

namespace sarmap {

PointBuffer read_pcd(const std::filesystem::path& path, PointCloudFileInfo* info = nullptr,
                     const InputLimits& limits = {});
void write_pcd(const std::filesystem::path& path, const PointBuffer& points,
               const PointCloudWriteOptions& options = {});

}  // namespace sarmap
