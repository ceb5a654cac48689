#include "engine/io/ply_header.hpp"

#include <optional>

#include "engine/core/error.hpp"
#include "engine/io/text_parse.hpp"

namespace sarmap {

bool PlyElement::has_lists() const {
  for (const PlyProperty& p : properties) {
    if (p.is_list) return true;
  }
  return false;
}

std::size_t PlyElement::min_record_size() const {
  std::size_t size = 0;
  for (const PlyProperty& p : properties) size += scalar_size(p.is_list ? p.list_count_type : p.type);
  return size;
}

std::string_view to_string(PlyEncoding encoding) {
  switch (encoding) {
    case PlyEncoding::Ascii: return "ascii";
    case PlyEncoding::BinaryLittleEndian: return "binary_little_endian";
    case PlyEncoding::BinaryBigEndian: return "binary_big_endian";
  }
  return "?";
}

PlyHeader parse_ply_header(std::string_view bytes, const std::string& file) {
  LineReader lines(bytes);
  std::string_view line;
  auto fail = [&](ErrorCode code, const std::string& what) -> Error {
    return Error(code, at_line(file, lines.line_number(), what));
  };
  if (!lines.next(line) || line != "ply") {
    throw fail(ErrorCode::Parse, "not a PLY file: expected the first line to be 'ply'");
  }
  PlyHeader header;
  bool have_format = false;
  while (true) {
    if (!lines.next(line)) {
      throw Error(ErrorCode::Parse,
                  at_line(file, lines.line_number(), "header ends without 'end_header' (file truncated?)"));
    }
    std::string_view rest = line;
    const std::string_view keyword = next_token(rest);
    if (keyword == "comment") {
      header.comments.emplace_back(trim(rest));
      continue;
    }
    if (keyword.empty() || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      const std::string_view name = next_token(rest);
      const std::string_view version = next_token(rest);
      if (name == "ascii") {
        header.encoding = PlyEncoding::Ascii;
      } else if (name == "binary_little_endian") {
        header.encoding = PlyEncoding::BinaryLittleEndian;
      } else if (name == "binary_big_endian") {
        throw fail(ErrorCode::Unsupported,
                   "format binary_big_endian is not supported; convert the file to binary_little_endian or ascii");
      } else {
        throw fail(ErrorCode::Parse, "unknown format '" + std::string(name) +
                                         "'; expected ascii, binary_little_endian or binary_big_endian");
      }
      if (version != "1.0") throw fail(ErrorCode::Unsupported, "PLY version '" + std::string(version) + "'; expected 1.0");
      have_format = true;
      continue;
    }
    if (keyword == "element") {
      PlyElement element;
      element.name = std::string(next_token(rest));
      const std::string_view count = next_token(rest);
      if (element.name.empty() || !parse_number(count, element.count) || !is_blank(rest)) {
        throw fail(ErrorCode::Parse, "expected 'element <name> <count>' with a non-negative integer count, got '" +
                                         std::string(line) + "'");
      }
      element.line = lines.line_number();
      header.elements.push_back(std::move(element));
      continue;
    }
    if (keyword == "property") {
      if (header.elements.empty()) throw fail(ErrorCode::Parse, "property declared before any element");
      PlyProperty property;
      property.line = lines.line_number();
      std::string_view type = next_token(rest);
      if (type == "list") {
        property.is_list = true;
        const std::string_view count_type = next_token(rest);
        const auto parsed_count = scalar_type_from_ply(count_type);
        if (!parsed_count || !is_integer(*parsed_count)) {
          throw fail(ErrorCode::Parse, "list count type '" + std::string(count_type) +
                                           "'; expected an integer type (uchar, ushort, int, ...)");
        }
        property.list_count_type = *parsed_count;
        type = next_token(rest);
      }
      const auto parsed = scalar_type_from_ply(type);
      if (!parsed) {
        throw fail(ErrorCode::Parse, "unknown property type '" + std::string(type) +
                                         "'; expected char, uchar, short, ushort, int, uint, float or double");
      }
      property.type = *parsed;
      property.name = std::string(next_token(rest));
      if (property.name.empty() || !is_blank(rest)) {
        throw fail(ErrorCode::Parse, "expected 'property <type> <name>', got '" + std::string(line) + "'");
      }
      for (const PlyProperty& other : header.elements.back().properties) {
        if (other.name == property.name) {
          throw fail(ErrorCode::Parse, "property '" + property.name + "' declared twice in element '" +
                                           header.elements.back().name + "'");
        }
      }
      header.elements.back().properties.push_back(std::move(property));
      continue;
    }
    throw fail(ErrorCode::Parse, "unknown header keyword '" + std::string(keyword) +
                                     "'; expected format, comment, obj_info, element, property or end_header");
  }
  if (!have_format) throw fail(ErrorCode::Parse, "header has no 'format' line");
  header.data_offset = lines.offset();
  header.header_lines = lines.line_number();
  return header;
}

}  // namespace sarmap
