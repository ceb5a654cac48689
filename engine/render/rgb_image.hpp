// An 8-bit RGB picture in memory: what the renderer draws into and the PNG
// writer stores. Panels are composed into one picture by pasting.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/classes.hpp"

namespace sarmap::render {

class RgbImage {
 public:
  RgbImage() = default;
  // Throws sarmap::Error (InvalidArgument) for a side that is not in
  // [1, kMaxImageSide].
  RgbImage(int width, int height, Rgb fill = {255, 255, 255});

  int width() const { return width_; }
  int height() const { return height_; }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }

  // x to the right, y down; the caller keeps (x, y) inside (contains).
  Rgb at(int x, int y) const {
    const std::uint8_t* p = &bytes_[offset(x, y)];
    return {p[0], p[1], p[2]};
  }
  void set(int x, int y, Rgb c) {
    std::uint8_t* p = &bytes_[offset(x, y)];
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
  }

  // Row-major, three bytes per pixel.
  std::span<const std::uint8_t> bytes() const { return bytes_; }

  // Copies `src` with its top-left corner at (x0, y0), clipped to this image.
  void paste(const RgbImage& src, int x0, int y0);

 private:
  std::size_t offset(int x, int y) const {
    return 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x));
  }
  int width_ = 0, height_ = 0;
  std::vector<std::uint8_t> bytes_;
};

// Larger sides are refused: a typo in --width should not allocate gigabytes.
inline constexpr int kMaxImageSide = 16384;

// Throws sarmap::Error (InvalidArgument) for a side outside [1, kMaxImageSide].
void check_image_size(int width, int height);

}  // namespace sarmap::render
