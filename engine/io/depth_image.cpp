// libpng reports errors by longjmp, which must not cross C++ frames that own
// objects: every libpng call therefore runs in a small function whose locals
// are all trivial, and the C++ side checks a status afterwards.
#include "engine/io/depth_image.hpp"

#include <png.h>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <span>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/file_bytes.hpp"

namespace sarmap {
namespace {

// Larger images are refused before allocating (a corrupt header could ask for gigabytes).
constexpr png_uint_32 kMaxDimension = 1u << 15;
constexpr double kMaxDeflateRatio = 1032.0;

struct PngSource {
  const unsigned char* data;
  std::size_t size;
  std::size_t offset;
  char message[256];
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* src = static_cast<PngSource*>(png_get_error_ptr(png));
  std::snprintf(src->message, sizeof src->message, "%s", message);
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

void read_from_memory(png_structp png, png_bytep out, png_size_t length) {
  auto* src = static_cast<PngSource*>(png_get_io_ptr(png));
  if (length > src->size - src->offset) {
    std::snprintf(src->message, sizeof src->message,
                  "file is truncated (ends at byte %zu, %zu more bytes expected)", src->size,
                  static_cast<std::size_t>(length - (src->size - src->offset)));
    png_longjmp(png, 1);
  }
  std::memcpy(out, src->data + src->offset, length);
  src->offset += length;
}

struct PngHeader {
  png_uint_32 width, height;
  int bit_depth, color_type, interlace;
};

// Returns false with src->message set on a libpng error.
bool read_header(png_structp png, png_infop info, PngHeader* header) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  png_get_IHDR(png, info, &header->width, &header->height, &header->bit_depth, &header->color_type,
               &header->interlace, nullptr, nullptr);
  return true;
}

// Reads all rows into `rows` (big-endian samples as stored); false on error.
bool read_rows(png_structp png, png_infop info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);
  return true;
}

std::string color_type_name(int color_type) {
  switch (color_type) {
    case PNG_COLOR_TYPE_GRAY:
      return "grayscale";
    case PNG_COLOR_TYPE_GRAY_ALPHA:
      return "grayscale + alpha";
    case PNG_COLOR_TYPE_RGB:
      return "RGB colour";
    case PNG_COLOR_TYPE_RGB_ALPHA:
      return "RGBA colour";
    case PNG_COLOR_TYPE_PALETTE:
      return "palette colour";
    default:
      return "colour type " + std::to_string(color_type);
  }
}

struct PngReader {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngReader() { png_destroy_read_struct(&png, info != nullptr ? &info : nullptr, nullptr); }
};

}  // namespace

DepthImage read_depth_png(const std::filesystem::path& path, const InputLimits& limits) {
  const std::string file = path.string();
  const FileBytes contents = read_file_bytes(path, limits.max_file_bytes);
  const std::span<const unsigned char> bytes(reinterpret_cast<const unsigned char*>(contents.data()),
                                             contents.size());
  if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0) {
    throw Error(ErrorCode::Parse, file + ": not a PNG file (bad signature)");
  }

  PngSource src{bytes.data(), bytes.size(), 0, {}};
  PngReader reader;
  reader.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &src, on_png_error, on_png_warning);
  if (reader.png == nullptr) throw Error(ErrorCode::Io, file + ": cannot create a PNG reader");
  reader.info = png_create_info_struct(reader.png);
  if (reader.info == nullptr) throw Error(ErrorCode::Io, file + ": cannot create a PNG reader");
  png_set_read_fn(reader.png, &src, read_from_memory);

  PngHeader h{};
  if (!read_header(reader.png, reader.info, &h)) {
    throw Error(ErrorCode::Parse, file + ": corrupt PNG header: " + src.message);
  }
  if (h.color_type != PNG_COLOR_TYPE_GRAY) {
    throw Error(ErrorCode::Unsupported, file + ": a depth image must be a 16-bit grayscale PNG, got " +
                                            std::to_string(h.bit_depth) + "-bit " +
                                            color_type_name(h.color_type));
  }
  if (h.bit_depth != 16) {
    throw Error(ErrorCode::Unsupported, file + ": a depth image must be a 16-bit grayscale PNG, got " +
                                            std::to_string(h.bit_depth) + "-bit grayscale");
  }
  if (h.width == 0 || h.height == 0 || h.width > kMaxDimension || h.height > kMaxDimension) {
    throw Error(ErrorCode::InvalidData, file + ": image size " + std::to_string(h.width) + "x" +
                                            std::to_string(h.height) + " is outside 1.." +
                                            std::to_string(kMaxDimension));
  }
  // Deflate cannot expand data more than 1032 times, so a file this small
  // cannot hold the image it declares: refuse it before allocating for it (a
  // 200-byte file declaring 32768 x 32768 had allocated 2 GB).
  const double declared_bytes = (2.0 * h.width + 1.0) * h.height;  // samples and a filter byte per row
  if (declared_bytes > kMaxDeflateRatio * static_cast<double>(bytes.size())) {
    throw Error(ErrorCode::InvalidData, file + ": declares a " + std::to_string(h.width) + "x" +
                                            std::to_string(h.height) + " image but holds only " +
                                            std::to_string(bytes.size()) +
                                            " bytes, too few for any compression of it");
  }
  if (static_cast<std::uint64_t>(h.width) * h.height > limits.max_points) {
    throw Error(ErrorCode::OutOfRange, file + ": a " + std::to_string(h.width) + "x" + std::to_string(h.height) +
                                           " image has more pixels than the limit of " +
                                           std::to_string(limits.max_points) + " points per scan (sarmap's --max-scan-points)");
  }
  if (h.interlace != PNG_INTERLACE_NONE) png_set_interlace_handling(reader.png);

  const std::size_t width = h.width;
  const std::size_t height = h.height;
  std::vector<unsigned char> raw(width * height * 2);
  std::vector<png_bytep> rows(height);
  for (std::size_t v = 0; v < height; ++v) rows[v] = raw.data() + v * width * 2;
  if (!read_rows(reader.png, reader.info, rows.data())) {
    throw Error(ErrorCode::Parse, file + ": corrupt PNG data: " + src.message);
  }

  DepthImage image;
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  image.pixels.resize(width * height);
  // PNG stores 16-bit samples big-endian.
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    image.pixels[i] = static_cast<std::uint16_t>((raw[2 * i] << 8) | raw[2 * i + 1]);
  }
  return image;
}

}  // namespace sarmap
