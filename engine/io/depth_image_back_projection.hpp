// Turns a depth image into points with the pinhole model, in the camera's
// optical frame (x right, y down, z forward): pixel (u, v) with depth d
// becomes ((u - cx) d / fx, (v - cy) d / fy, d).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "engine/core/point_buffer.hpp"
#include "engine/core/pose.hpp"
#include "engine/core/scan.hpp"
#include "engine/core/sensor_info.hpp"
#include "engine/io/depth_image.hpp"
#include "engine/io/input_limits.hpp"

namespace sarmap {

struct DepthDecoding {
  // Raw samples per metre: 5000 for TUM RGB-D, 1000 for 7-Scenes (millimetres).
  double units_per_metre = 1000.0;
  // Raw 0 always means "no measurement"; some datasets also mark 65535 so.
  bool max_value_is_invalid = false;
  // Depths beyond this (metres) are dropped; 0 keeps all.
  double max_depth = 0.0;
  // The image file's size and pixel count (max_points).
  InputLimits limits;
};

// Valid pixels only, in row-major pixel order. Throws InvalidData when the
// intrinsics name an image size other than the image's.
PointBuffer back_project(const DepthImage& image, const PinholeIntrinsics& intrinsics,
                         const DepthDecoding& decoding);

// read_depth_png + back_project, with the file named in every error.
PointBuffer read_depth_png_points(const std::filesystem::path& path, const PinholeIntrinsics& intrinsics,
                                  const DepthDecoding& decoding);

// One posed depth frame of a sequence (TUM, 7-Scenes) as a Scan: its points
// moved into the world frame by the camera pose, rays starting at the camera.
Scan read_depth_png_scan(const std::filesystem::path& path, const PinholeIntrinsics& intrinsics,
                         const DepthDecoding& decoding, const Pose& pose, double timestamp,
                         std::size_t index);

}  // namespace sarmap
