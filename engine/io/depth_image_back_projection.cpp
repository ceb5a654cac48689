#include "engine/io/depth_image_back_projection.hpp"

#include <string>
#include <vector>

#include "engine/core/error.hpp"

namespace sarmap {

PointBuffer back_project(const DepthImage& image, const PinholeIntrinsics& k, const DepthDecoding& decoding) {
  if ((k.width != 0 && k.width != image.width) || (k.height != 0 && k.height != image.height)) {
    throw Error(ErrorCode::InvalidData, "depth image is " + std::to_string(image.width) + "x" +
                                            std::to_string(image.height) + " but the intrinsics are for " +
                                            std::to_string(k.width) + "x" + std::to_string(k.height));
  }
  if (!(decoding.units_per_metre > 0)) {
    throw Error(ErrorCode::InvalidArgument, "depth decoding: units_per_metre must be positive");
  }
  const double max_raw = decoding.max_depth > 0 ? decoding.max_depth * decoding.units_per_metre : 65536.0;
  auto valid = [&](std::uint16_t raw) {
    return raw != 0 && !(decoding.max_value_is_invalid && raw == 0xFFFF) && raw <= max_raw;
  };

  std::size_t count = 0;
  for (const std::uint16_t raw : image.pixels) count += valid(raw) ? 1 : 0;

  // Per-column and per-row ray slopes, so each pixel costs two multiplies.
  std::vector<double> slope_x(static_cast<std::size_t>(image.width));
  std::vector<double> slope_y(static_cast<std::size_t>(image.height));
  for (int u = 0; u < image.width; ++u) slope_x[static_cast<std::size_t>(u)] = (u - k.cx) / k.fx;
  for (int v = 0; v < image.height; ++v) slope_y[static_cast<std::size_t>(v)] = (v - k.cy) / k.fy;

  PointBuffer points(count);
  auto xs = points.x();
  auto ys = points.y();
  auto zs = points.z();
  std::size_t out = 0;
  for (int v = 0; v < image.height; ++v) {
    for (int u = 0; u < image.width; ++u) {
      const std::uint16_t raw = image.at(u, v);
      if (!valid(raw)) continue;
      const double d = raw / decoding.units_per_metre;
      xs[out] = static_cast<float>(slope_x[static_cast<std::size_t>(u)] * d);
      ys[out] = static_cast<float>(slope_y[static_cast<std::size_t>(v)] * d);
      zs[out] = static_cast<float>(d);
      ++out;
    }
  }
  return points;
}

PointBuffer read_depth_png_points(const std::filesystem::path& path, const PinholeIntrinsics& intrinsics,
                                  const DepthDecoding& decoding) {
  const DepthImage image = read_depth_png(path, decoding.limits);
  try {
    return back_project(image, intrinsics, decoding);
  } catch (const Error& e) {
    throw Error(e.code(), path.string() + ": " + e.what());
  }
}

Scan read_depth_png_scan(const std::filesystem::path& path, const PinholeIntrinsics& intrinsics,
                         const DepthDecoding& decoding, const Pose& pose, double timestamp,
                         std::size_t index) {
  Scan scan;
  scan.points = read_depth_png_points(path, intrinsics, decoding);
  pose.apply(scan.points);
  scan.pose = pose;
  scan.origin = pose.translation();
  scan.timestamp = timestamp;
  scan.index = index;
  scan.source = path.string();
  return scan;
}

}  // namespace sarmap
