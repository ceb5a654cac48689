// libpng reports errors by longjmp, which must not cross C++ frames that own
// objects: the libpng calls run in one function whose locals are all plain,
// and the encoded bytes are collected in memory, then written atomically.
#include "engine/render/png_file.hpp"

#include <png.h>

#include <csetjmp>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"

namespace sarmap::render {
namespace {

struct PngSink {
  std::vector<std::uint8_t> bytes;
  std::string message;
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* sink = static_cast<PngSink*>(png_get_error_ptr(png));
  sink->message = message != nullptr ? message : "libpng error";
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

void append_bytes(png_structp png, png_bytep data, png_size_t length) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  bool grown = true;
  try {
    sink->bytes.insert(sink->bytes.end(), data, data + length);
  } catch (...) {
    grown = false;  // no C++ exception may unwind through libpng's C frames
  }
  if (!grown) png_error(png, "out of memory");
}

void flush_nothing(png_structp) {}

// Returns false with sink->message set on a libpng error.
bool encode(png_structp png, png_infop info, PngSink* sink, png_uint_32 width, png_uint_32 height,
            png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_write_fn(png, sink, append_bytes, flush_nothing);
  png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

struct PngWriter {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngWriter() { png_destroy_write_struct(&png, info != nullptr ? &info : nullptr); }
};

}  // namespace

void write_png(const RgbImage& image, const std::filesystem::path& path) {
  if (image.width() < 1 || image.height() < 1) {
    throw Error(ErrorCode::InvalidArgument, path.string() + ": cannot write an empty image");
  }
  PngSink sink;
  PngWriter writer;
  writer.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, on_png_error, on_png_warning);
  if (writer.png == nullptr) throw Error(ErrorCode::Io, path.string() + ": cannot create a PNG writer");
  writer.info = png_create_info_struct(writer.png);
  if (writer.info == nullptr) throw Error(ErrorCode::Io, path.string() + ": cannot create a PNG writer");
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height()));
  const std::size_t row_bytes = 3 * static_cast<std::size_t>(image.width());
  // libpng takes non-const row pointers but only reads them when writing.
  auto* data = const_cast<png_bytep>(image.bytes().data());
  for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = data + y * row_bytes;
  if (!encode(writer.png, writer.info, &sink, static_cast<png_uint_32>(image.width()),
              static_cast<png_uint_32>(image.height()), rows.data())) {
    throw Error(ErrorCode::Io, path.string() + ": cannot encode the PNG: " + sink.message);
  }
  AtomicFileWriter out(path);
  out.write(sink.bytes.data(), sink.bytes.size());
  out.commit();
}

}  // namespace sarmap::render
