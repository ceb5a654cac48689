// The header of a PCD v0.7 file (FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT,
// VIEWPOINT, POINTS, DATA), parsed and cross-checked apart from the data.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "engine/io/scalar_type.hpp"

namespace sarmap {

enum class PcdEncoding { Ascii, Binary, BinaryCompressed };

struct PcdField {
  std::string name;
  ScalarType type = ScalarType::Float32;
  std::size_t count = 1;  // values per point (COUNT)

  std::size_t bytes() const { return scalar_size(type) * count; }
};

struct PcdHeader {
  std::vector<PcdField> fields;
  std::uint64_t width = 0;
  std::uint64_t height = 1;
  std::uint64_t points = 0;
  PcdEncoding encoding = PcdEncoding::Ascii;
  std::size_t data_offset = 0;   // first byte after the DATA line
  std::size_t header_lines = 0;  // lines up to and including DATA
  std::size_t fields_line = 0;
  std::size_t type_line = 0;
  std::size_t count_line = 0;    // 0 when COUNT is absent (every count is 1)
  std::size_t points_line = 0;   // the POINTS line (or WIDTH when POINTS is absent)
  std::vector<std::string> comments;  // text after '#' of each comment line but the ".PCD v0.7" banner

  // Bytes of one point in the binary encodings.
  std::size_t point_size() const;
};

std::string_view to_string(PcdEncoding encoding);

// Throws sarmap::Error (Parse, Unsupported) naming file and header line.
PcdHeader parse_pcd_header(std::string_view bytes, const std::string& file);

}  // namespace sarmap
