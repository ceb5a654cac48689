// An RgbImage as an 8-bit RGB PNG file (libpng), written atomically: a
// failed or interrupted write leaves the old file or none, never half a
// picture.
#pragma once

#include <filesystem>

#include "engine/render/rgb_image.hpp"

namespace sarmap::render {

// Throws sarmap::Error (Io) naming the file when it cannot be written, and
// for an empty image (InvalidArgument).
void write_png(const RgbImage& image, const std::filesystem::path& path);

}  // namespace sarmap::render
