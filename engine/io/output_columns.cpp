#include "engine/io/output_columns.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <vector>

#include "engine/core/error.hpp"

namespace sarmap {

static_assert(std::endian::native == std::endian::little, "binary point-cloud encoding assumes a little-endian host");

namespace {

std::uint32_t packed_rgb(const OutputColumn& c, std::size_t i) {
  if (c.green == nullptr) return c.u8[i];
  return (std::uint32_t{c.u8[i]} << 16) | (std::uint32_t{c.green[i]} << 8) | c.blue[i];
}

// Writes value i of a column at dst and returns its size.
std::size_t encode_value(const OutputColumn& c, std::size_t i, char* dst) {
  switch (c.type) {
    case ScalarType::UInt8: *dst = static_cast<char>(c.u8[i]); return 1;
    case ScalarType::UInt32: {
      const std::uint32_t v = packed_rgb(c, i);
      std::memcpy(dst, &v, 4);
      return 4;
    }
    default: std::memcpy(dst, &c.f[i], 4); return 4;
  }
}

// Points per buffer flushed to the file: large enough that write() calls cost
// nothing, small enough to stay in cache.
constexpr std::size_t kChunkPoints = 16384;

}  // namespace

std::size_t record_size(std::span<const OutputColumn> columns) {
  std::size_t size = 0;
  for (const OutputColumn& c : columns) size += scalar_size(c.type);
  return size;
}

void write_binary_records(AtomicFileWriter& out, std::span<const OutputColumn> columns, std::size_t count) {
  const std::size_t stride = record_size(columns);
  std::vector<char> buffer(std::min(count, kChunkPoints) * stride);
  for (std::size_t start = 0; start < count; start += kChunkPoints) {
    const std::size_t n = std::min(kChunkPoints, count - start);
    std::size_t offset = 0;
    for (const OutputColumn& c : columns) {
      for (std::size_t i = 0; i < n; ++i) encode_value(c, start + i, buffer.data() + i * stride + offset);
      offset += scalar_size(c.type);
    }
    out.write(buffer.data(), n * stride);
  }
}

void encode_binary_columns(std::span<const OutputColumn> columns, std::size_t count, char* dst) {
  for (const OutputColumn& c : columns) {
    const std::size_t size = scalar_size(c.type);
    for (std::size_t i = 0; i < count; ++i) encode_value(c, i, dst + i * size);
    dst += count * size;
  }
}

void write_text_records(AtomicFileWriter& out, std::span<const OutputColumn> columns, std::size_t count) {
  std::string buffer;
  // Longest value: a float's shortest round-trip form is at most 15 characters.
  const std::size_t max_line = columns.size() * 16 + 1;
  buffer.reserve(kChunkPoints * max_line);
  char text[32];
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const OutputColumn& c = columns[k];
      std::to_chars_result r{};
      switch (c.type) {
        case ScalarType::UInt8: r = std::to_chars(text, text + sizeof(text), unsigned{c.u8[i]}); break;
        case ScalarType::UInt32: r = std::to_chars(text, text + sizeof(text), packed_rgb(c, i)); break;
        default: r = std::to_chars(text, text + sizeof(text), c.f[i]); break;
      }
      if (k > 0) buffer += ' ';
      buffer.append(text, r.ptr);
    }
    buffer += '\n';
    if (buffer.size() + max_line > buffer.capacity()) {
      out.write(buffer);
      buffer.clear();
    }
  }
  out.write(buffer);
}

std::string header_comment_lines(const std::vector<std::string>& comments, std::string_view prefix,
                                 const std::filesystem::path& file) {
  std::string lines;
  for (const std::string& comment : comments) {
    if (comment.find_first_of("\r\n") != std::string::npos) {
      throw Error(ErrorCode::InvalidArgument,
                  file.string() + ": header comment '" + comment + "' holds a line break");
    }
    lines.append(prefix);
    lines += comment;
    lines += '\n';
  }
  return lines;
}

}  // namespace sarmap
