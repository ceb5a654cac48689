// Errors here are test-setup failures, so libpng's longjmp is turned into a
// gtest failure in the one function that calls libpng.
#include "png_test_writer.hpp"

#include <png.h>
#include <csetjmp>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace sarmap::test {
namespace {

// channels: 1 (gray) or 3 (RGB); bit_depth 8 or 16. `rows` are fully encoded.
bool write_png(const char* path, int width, int height, int bit_depth, int color_type,
               std::vector<png_bytep>& rows) {
  std::FILE* file = std::fopen(path, "wb");
  if (file == nullptr) return false;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bit_depth,
               color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return std::fclose(file) == 0;
}

void write_or_throw(const std::filesystem::path& path, int width, int height, int bit_depth, int color_type,
                    std::vector<std::uint8_t>& bytes, std::size_t row_bytes) {
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  for (std::size_t v = 0; v < rows.size(); ++v) rows[v] = bytes.data() + v * row_bytes;
  if (!write_png(path.c_str(), width, height, bit_depth, color_type, rows)) {
    throw std::runtime_error("test setup: cannot write " + path.string());
  }
}

// PNG samples are big-endian.
void put16(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint16_t value) {
  bytes[at] = static_cast<std::uint8_t>(value >> 8);
  bytes[at + 1] = static_cast<std::uint8_t>(value & 0xFF);
}

}  // namespace

void write_png_gray16(const std::filesystem::path& path, int width, int height,
                      const std::vector<std::uint16_t>& pixels) {
  std::vector<std::uint8_t> bytes(pixels.size() * 2);
  for (std::size_t i = 0; i < pixels.size(); ++i) put16(bytes, 2 * i, pixels[i]);
  write_or_throw(path, width, height, 16, PNG_COLOR_TYPE_GRAY, bytes, static_cast<std::size_t>(width) * 2);
}

void write_png_gray8(const std::filesystem::path& path, int width, int height,
                     const std::vector<std::uint8_t>& pixels) {
  std::vector<std::uint8_t> bytes = pixels;
  write_or_throw(path, width, height, 8, PNG_COLOR_TYPE_GRAY, bytes, static_cast<std::size_t>(width));
}

void write_png_rgb16(const std::filesystem::path& path, int width, int height,
                     const std::vector<std::uint16_t>& pixels) {
  std::vector<std::uint8_t> bytes(pixels.size() * 6);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    for (std::size_t c = 0; c < 3; ++c) put16(bytes, 6 * i + 2 * c, pixels[i]);
  }
  write_or_throw(path, width, height, 16, PNG_COLOR_TYPE_RGB, bytes, static_cast<std::size_t>(width) * 6);
}

}  // namespace sarmap::test
