// The columns a writer emits for a PointBuffer (name, file type, source
// array) and the encoders for their data sections: binary records, binary
// columns (PCD binary_compressed) and text lines. PLY and PCD differ only in
// names and headers, so both writers share these.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/io/atomic_file.hpp"
#include "engine/io/scalar_type.hpp"

namespace sarmap {

struct OutputColumn {
  std::string name;
  // Float32 (from f), UInt8 (from u8), or UInt32: packed 0x00RRGGBB from
  // u8 (red), green and blue when green is set, else u8 widened (PCD labels).
  ScalarType type = ScalarType::Float32;
  const float* f = nullptr;
  const std::uint8_t* u8 = nullptr;
  const std::uint8_t* green = nullptr;
  const std::uint8_t* blue = nullptr;
};

std::size_t record_size(std::span<const OutputColumn> columns);

// Writes count points as little-endian records, one after another.
void write_binary_records(AtomicFileWriter& out, std::span<const OutputColumn> columns, std::size_t count);
// Encodes every column in turn (all x, then all y, ...) into dst, which holds
// count * record_size(columns) bytes.
void encode_binary_columns(std::span<const OutputColumn> columns, std::size_t count, char* dst);
// Writes one line per point, values separated by spaces; floats in the
// shortest form that reads back to the same value.
void write_text_records(AtomicFileWriter& out, std::span<const OutputColumn> columns, std::size_t count);

// Header comment lines, each as prefix + text + "\n" (PLY "comment ", PCD
// "# "). Throws sarmap::Error (InvalidArgument) naming the file for a
// comment that holds a line break, which would end the comment early.
std::string header_comment_lines(const std::vector<std::string>& comments, std::string_view prefix,
                                 const std::filesystem::path& file);

}  // namespace sarmap
