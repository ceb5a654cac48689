#include "engine/render/rgb_image.hpp"

#include <algorithm>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::render {

void check_image_size(int width, int height) {
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide) {
    throw Error(ErrorCode::InvalidArgument, "image size " + std::to_string(width) + " x " +
                                                std::to_string(height) + " is not within 1 to " +
                                                std::to_string(kMaxImageSide) + " pixels a side");
  }
}

RgbImage::RgbImage(int width, int height, Rgb fill) : width_(width), height_(height) {
  check_image_size(width, height);
  bytes_.resize(3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (std::size_t i = 0; i < bytes_.size(); i += 3) {
    bytes_[i] = fill.r;
    bytes_[i + 1] = fill.g;
    bytes_[i + 2] = fill.b;
  }
}

void RgbImage::paste(const RgbImage& src, int x0, int y0) {
  const int xa = std::max(0, x0), xb = std::min(width_, x0 + src.width());
  if (xa >= xb) return;
  for (int y = std::max(0, y0); y < std::min(height_, y0 + src.height()); ++y) {
    const std::uint8_t* from = &src.bytes_[src.offset(xa - x0, y - y0)];
    std::copy(from, from + 3 * static_cast<std::size_t>(xb - xa), &bytes_[offset(xa, y)]);
  }
}

}  // namespace sarmap::render
