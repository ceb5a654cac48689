// Reading and writing whole point clouds, with the format chosen by the file
// extension (.ply or .pcd). Readers drop points with NaN/Inf coordinates and
// count them; writers are atomic.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/point_buffer.hpp"
#include "engine/io/input_limits.hpp"

namespace sarmap {

enum class PointCloudFormat { Ply, Pcd };

// What a reader found besides the points.
struct PointCloudFileInfo {
  PointCloudFormat format = PointCloudFormat::Ply;
  std::string encoding;               // "ascii", "binary_little_endian", "binary", "binary_compressed"
  std::vector<std::string> fields;    // property / field names as written in the file
  std::size_t points_in_file = 0;     // as declared by the header
  std::size_t dropped_non_finite = 0; // points dropped for NaN/Inf coordinates
  std::vector<std::string> comments{};  // PLY 'comment' lines, PCD '#' lines, without the keyword
};

struct PointCloudWriteOptions {
  bool binary = true;  // false writes ASCII
  // PCD only, with binary: DATA binary_compressed (LZF, stored field by field).
  // PLY has no compressed encoding and ignores it.
  bool compressed = false;
  // Header comment lines after "written by sarmap" (PLY 'comment', PCD '#'),
  // e.g. "voxel_size 0.05". A line break in one is refused (InvalidArgument).
  std::vector<std::string> comments{};
};

// Throws sarmap::Error for an unknown extension or a malformed file.
PointCloudFormat point_cloud_format_of(const std::filesystem::path& path);
// Throws sarmap::Error naming the file: Io, Parse, or OutOfRange past `limits`
// (a file too large, or a header declaring more points than max_points).
PointBuffer read_point_cloud(const std::filesystem::path& path, PointCloudFileInfo* info = nullptr,
                             const InputLimits& limits = {});
void write_point_cloud(const std::filesystem::path& path, const PointBuffer& points,
                       const PointCloudWriteOptions& options = {});

}  // namespace sarmap
