// A 16-bit depth image as RGB-D datasets store it (one unsigned sample per
// pixel, in dataset-specific units), and its reader for 16-bit grayscale PNG.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "engine/io/input_limits.hpp"

namespace sarmap {

struct DepthImage {
  int width = 0;
  int height = 0;
  // Row-major, width * height raw samples (host byte order).
  std::vector<std::uint16_t> pixels;

  std::uint16_t at(int u, int v) const {
    return pixels[static_cast<std::size_t>(v) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(u)];
  }
};

// Reads a 16-bit single-channel (grayscale) PNG. An 8-bit or colour PNG, a
// truncated or corrupt file get a sarmap::Error naming the file and the
// problem; the image is never partially returned. A file or an image larger
// than `limits` (max_file_bytes, max_points pixels) is refused (OutOfRange)
// before anything is allocated for it.
DepthImage read_depth_png(const std::filesystem::path& path, const InputLimits& limits = {});

}  // namespace sarmap
