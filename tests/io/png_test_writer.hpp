// Test-only PNG writer (libpng), independent of the engine's reader, so the
// reader is checked against files it did not produce. Writes 16-bit depth
// images and the 8-bit / colour images a depth reader must refuse.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace sarmap::test {

// Grayscale PNG with 16-bit samples (row-major, width * height values).
void write_png_gray16(const std::filesystem::path& path, int width, int height,
                      const std::vector<std::uint16_t>& pixels);
// Grayscale PNG with 8-bit samples.
void write_png_gray8(const std::filesystem::path& path, int width, int height,
                     const std::vector<std::uint8_t>& pixels);
// 16-bit RGB PNG, every channel set to the same sample.
void write_png_rgb16(const std::filesystem::path& path, int width, int height,
                     const std::vector<std::uint16_t>& pixels);

}  // namespace sarmap::test
