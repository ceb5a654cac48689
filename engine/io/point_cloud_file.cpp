// Chooses the PLY or PCD reader/writer from the file extension.
#include "engine/io/point_cloud_file.hpp"

#include <algorithm>
#include <cctype>

#include "engine/core/error.hpp"
#include "engine/io/pcd.hpp"
#include "engine/io/ply.hpp"

namespace sarmap {

PointCloudFormat point_cloud_format_of(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".ply") return PointCloudFormat::Ply;
  if (extension == ".pcd") return PointCloudFormat::Pcd;
  throw Error(ErrorCode::Unsupported, path.string() + ": unknown point-cloud extension '" +
                                          path.extension().string() + "'; expected .ply or .pcd");
}

PointBuffer read_point_cloud(const std::filesystem::path& path, PointCloudFileInfo* info, const InputLimits& limits) {
  switch (point_cloud_format_of(path)) {
    case PointCloudFormat::Ply: return read_ply(path, info, limits);
    case PointCloudFormat::Pcd: return read_pcd(path, info, limits);
  }
  return {};
}

void write_point_cloud(const std::filesystem::path& path, const PointBuffer& points,
                       const PointCloudWriteOptions& options) {
  switch (point_cloud_format_of(path)) {
    case PointCloudFormat::Ply: write_ply(path, points, options); return;
    case PointCloudFormat::Pcd: write_pcd(path, points, options); return;
  }
}

}  // namespace sarmap
