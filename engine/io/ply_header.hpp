// The header of a PLY file: format, elements and their properties, and where
// the data starts. Parsed apart from the data so the reader can validate every
// declared size against the file before it allocates anything.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "engine/io/scalar_type.hpp"

namespace sarmap {

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::Float32;  // the item type of a list
  bool is_list = false;
  ScalarType list_count_type = ScalarType::UInt8;
  std::size_t line = 0;  // header line that declares it
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t line = 0;

  bool has_lists() const;
  // Bytes of one binary record; for lists, the smallest possible record (empty lists).
  std::size_t min_record_size() const;
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
  std::size_t data_offset = 0;     // first byte after the end_header line
  std::size_t header_lines = 0;    // lines up to and including end_header
  std::vector<std::string> comments;  // text of each 'comment' line, in order
};

std::string_view to_string(PlyEncoding encoding);

// Throws sarmap::Error (Parse, Unsupported) naming file and header line.
PlyHeader parse_ply_header(std::string_view bytes, const std::string& file);

}  // namespace sarmap
