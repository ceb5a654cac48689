// Reads PLY point clouds (ASCII and binary little-endian) into a PointBuffer.
// Every size the header declares is checked against the bytes actually there
// before anything is allocated; binary vertices are decoded column by column
// straight into the buffer's arrays.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/field_binding.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/ply.hpp"
#include "engine/io/ply_header.hpp"
#include "engine/io/text_parse.hpp"

namespace sarmap {
namespace {

constexpr int kUnboundProperty = -1;

// The vertex properties sarmap keeps, and for each property its binding (or kUnboundProperty).
struct VertexLayout {
  std::vector<FieldBinding> bindings;
  std::vector<int> binding_of_property;
};

VertexLayout bind_vertex_properties(const PlyElement& vertex, const std::string& file) {
  VertexLayout layout;
  bool has[3] = {false, false, false};
  for (const PlyProperty& p : vertex.properties) {
    const auto attribute = attribute_from_ply_name(p.name);
    if (!attribute) {
      layout.binding_of_property.push_back(kUnboundProperty);
      continue;
    }
    if (p.is_list) {
      throw Error(ErrorCode::Parse, at_line(file, p.line, "property '" + p.name + "' is a list; expected a single value"));
    }
    const std::string expected = expected_type_for(*attribute, p.type);
    if (!expected.empty()) {
      throw Error(ErrorCode::Parse, at_line(file, p.line, "property '" + p.name + "' has type " +
                                                              std::string(ply_type_name(p.type)) + "; expected " +
                                                              expected));
    }
    if (*attribute <= PointAttribute::Z) has[static_cast<int>(*attribute)] = true;
    FieldBinding b;
    b.name = p.name;
    b.attribute = *attribute;
    b.type = p.type;
    if (*attribute == PointAttribute::Score) b.score_name = score_name_of(p.name);
    layout.binding_of_property.push_back(static_cast<int>(layout.bindings.size()));
    layout.bindings.push_back(std::move(b));
  }
  static constexpr const char* kAxes[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    if (!has[axis]) {
      throw Error(ErrorCode::Parse, at_line(file, vertex.line, std::string("element vertex has no property '") +
                                                                   kAxes[axis] + "'; x, y and z are required"));
    }
  }
  return layout;
}

void enable_bound_attributes(PointBuffer& points, const VertexLayout& layout) {
  for (const FieldBinding& b : layout.bindings) enable_attribute(points, b);
}

// ---------------------------------------------------------------- binary

template <class T>
T load(const char* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

std::int64_t load_list_count(const char* p, ScalarType type) {
  switch (type) {
    case ScalarType::Int8: return load<std::int8_t>(p);
    case ScalarType::UInt8: return load<std::uint8_t>(p);
    case ScalarType::Int16: return load<std::int16_t>(p);
    case ScalarType::UInt16: return load<std::uint16_t>(p);
    case ScalarType::Int32: return load<std::int32_t>(p);
    case ScalarType::UInt32: return load<std::uint32_t>(p);
    default: return -1;  // the header parser accepts only these count types
  }
}

// Walks `count` records of an element starting at offset and returns the
// offset after them, checking every list against the file's end.
std::size_t skip_records(std::string_view bytes, std::size_t offset, const PlyElement& element, std::uint64_t count,
                         const std::string& file) {
  if (!element.has_lists()) {
    const std::size_t size = element.min_record_size();
    if (size > 0 && count > (bytes.size() - offset) / size) {
      throw Error(ErrorCode::Parse,
                  at_offset(file, offset, "element '" + element.name + "' declares " + std::to_string(element.count) +
                                              " records of " + std::to_string(size) + " bytes but only " +
                                              std::to_string(bytes.size() - offset) + " bytes remain"));
    }
    return offset + static_cast<std::size_t>(count) * size;
  }
  for (std::uint64_t r = 0; r < count; ++r) {
    for (const PlyProperty& p : element.properties) {
      const std::size_t head = scalar_size(p.is_list ? p.list_count_type : p.type);
      if (head > bytes.size() - offset) {
        throw Error(ErrorCode::Parse,
                    at_offset(file, offset, "file ends inside record " + std::to_string(r) + " of element '" +
                                                element.name + "' (property '" + p.name + "'); the header declares " +
                                                std::to_string(element.count) + " records"));
      }
      if (!p.is_list) {
        offset += head;
        continue;
      }
      const std::int64_t items = load_list_count(bytes.data() + offset, p.list_count_type);
      if (items < 0) {
        throw Error(ErrorCode::Parse, at_offset(file, offset, "list '" + p.name + "' has negative length " +
                                                                  std::to_string(items)));
      }
      offset += head;
      const std::size_t item_size = scalar_size(p.type);
      if (static_cast<std::uint64_t>(items) > (bytes.size() - offset) / item_size) {
        throw Error(ErrorCode::Parse, at_offset(file, offset, "file ends inside list '" + p.name + "' of " +
                                                                  std::to_string(items) + " items in record " +
                                                                  std::to_string(r) + " of element '" +
                                                                  element.name + "'"));
      }
      offset += static_cast<std::size_t>(items) * item_size;
    }
  }
  return offset;
}

[[noreturn]] void throw_bad_label(const std::string& file, std::size_t offset, const FieldBinding& b,
                                  std::size_t vertex, std::int64_t value) {
  throw Error(ErrorCode::InvalidData, at_offset(file, offset, "property '" + b.name + "' of vertex " +
                                                                  std::to_string(vertex) + " is " +
                                                                  std::to_string(value) + "; expected a class id in 0..255"));
}

void read_binary_vertices(std::string_view bytes, std::size_t offset, const PlyElement& vertex, VertexLayout& layout,
                          PointBuffer& points, const std::string& file, const InputLimits& limits) {
  const std::size_t min_size = vertex.min_record_size();
  const std::size_t remaining = bytes.size() - offset;
  if (vertex.count > remaining / min_size) {
    throw Error(ErrorCode::Parse,
                at_offset(file, offset, "header declares " + std::to_string(vertex.count) + " vertices of " +
                                            (vertex.has_lists() ? "at least " : "") + std::to_string(min_size) +
                                            " bytes but only " + std::to_string(remaining) +
                                            " bytes of data follow the header (file truncated or count wrong)"));
  }
  // After the size check, whose error says more of a lying header.
  check_declared_points(vertex.count, limits, file);
  const auto count = static_cast<std::size_t>(vertex.count);
  points.resize(count);
  enable_bound_attributes(points, layout);

  if (!vertex.has_lists()) {
    std::size_t field_offset = 0;
    std::size_t b = 0;
    for (std::size_t k = 0; k < vertex.properties.size(); ++k) {
      if (layout.binding_of_property[k] != kUnboundProperty) {
        layout.bindings[b].offset = field_offset;
        layout.bindings[b].stride = min_size;
        ++b;
      }
      field_offset += scalar_size(vertex.properties[k].type);
    }
    const auto failure = decode_binary_fields(bytes.data() + offset, count, layout.bindings, points, 0);
    if (failure) {
      const FieldBinding& bad = layout.bindings[failure->binding];
      throw_bad_label(file, offset + failure->point * min_size + bad.offset, bad, failure->point, failure->value);
    }
    return;
  }

  // Lists make records variable-sized: copy the kept values of each record
  // into a packed fixed-size layout, then decode that like any other.
  std::size_t packed_stride = 0;
  for (FieldBinding& b : layout.bindings) {
    b.offset = packed_stride;
    packed_stride += scalar_size(b.type);
  }
  for (FieldBinding& b : layout.bindings) b.stride = packed_stride;
  std::vector<char> packed(count * packed_stride);
  std::size_t at = offset;
  for (std::size_t r = 0; r < count; ++r) {
    const std::size_t record = at;
    at = skip_records(bytes, record, vertex, 1, file);
    std::size_t cursor = record;
    for (std::size_t k = 0; k < vertex.properties.size(); ++k) {
      const PlyProperty& p = vertex.properties[k];
      if (p.is_list) {
        const std::int64_t items = load_list_count(bytes.data() + cursor, p.list_count_type);
        cursor += scalar_size(p.list_count_type) + static_cast<std::size_t>(items) * scalar_size(p.type);
        continue;
      }
      const int b = layout.binding_of_property[k];
      if (b != kUnboundProperty) {
        std::memcpy(packed.data() + r * packed_stride + layout.bindings[b].offset, bytes.data() + cursor,
                    scalar_size(p.type));
      }
      cursor += scalar_size(p.type);
    }
  }
  const auto failure = decode_binary_fields(packed.data(), count, layout.bindings, points, 0);
  if (failure) {
    const std::size_t record = skip_records(bytes, offset, vertex, failure->point, file);
    throw_bad_label(file, record, layout.bindings[failure->binding], failure->point, failure->value);
  }
}

// ---------------------------------------------------------------- ascii

// Lines of ASCII data with line numbers that continue the header's.
class DataLines {
 public:
  DataLines(std::string_view data, std::size_t header_lines) : lines_(data), first_(header_lines) {}
  // The next line that holds something; false at the end of the file.
  bool next_nonblank(std::string_view& line) {
    while (lines_.next(line)) {
      if (!is_blank(line)) return true;
    }
    return false;
  }
  std::size_t line_number() const { return first_ + lines_.line_number(); }

 private:
  LineReader lines_;
  std::size_t first_;
};

void skip_ascii_element(DataLines& lines, const PlyElement& element, const std::string& file) {
  std::string_view line;
  for (std::uint64_t r = 0; r < element.count; ++r) {
    if (!lines.next_nonblank(line)) {
      throw Error(ErrorCode::Parse, at_line(file, lines.line_number(), "file ends after " + std::to_string(r) +
                                                                           " of the " + std::to_string(element.count) +
                                                                           " '" + element.name +
                                                                           "' records the header declares"));
    }
  }
}

void read_ascii_vertices(DataLines& lines, std::size_t remaining_bytes, const PlyElement& vertex,
                         const VertexLayout& layout, PointBuffer& points, const std::string& file,
                         const InputLimits& limits) {
  // Each value takes at least one character and one separator.
  const std::size_t min_bytes = 2 * vertex.properties.size();
  if (vertex.count > (remaining_bytes + 1) / min_bytes) {
    throw Error(ErrorCode::Parse,
                at_line(file, vertex.line, "header declares " + std::to_string(vertex.count) +
                                               " vertices but only " + std::to_string(remaining_bytes) +
                                               " bytes of data follow (at least " + std::to_string(min_bytes) +
                                               " per vertex): file truncated or count wrong"));
  }
  check_declared_points(vertex.count, limits, file);
  const auto count = static_cast<std::size_t>(vertex.count);
  points.resize(count);
  enable_bound_attributes(points, layout);
  std::string_view line;
  std::string expected;
  for (std::size_t i = 0; i < count; ++i) {
    if (!lines.next_nonblank(line)) {
      throw Error(ErrorCode::Parse, at_line(file, lines.line_number(),
                                            "file ends after " + std::to_string(i) + " of the " +
                                                std::to_string(count) + " vertices the header declares"));
    }
    auto fail = [&](const std::string& what) {
      return Error(ErrorCode::Parse, at_line(file, lines.line_number(), "vertex " + std::to_string(i) + ": " + what));
    };
    std::string_view rest = line;
    for (std::size_t k = 0; k < vertex.properties.size(); ++k) {
      const PlyProperty& p = vertex.properties[k];
      std::string_view token = next_token(rest);
      if (token.empty()) {
        throw fail("line ends before property '" + p.name + "' (value " + std::to_string(k + 1) + " of " +
                   std::to_string(vertex.properties.size()) + ")");
      }
      if (p.is_list) {
        std::int64_t items = 0;
        if (!parse_number(token, items) || items < 0) {
          throw fail("list '" + p.name + "' length '" + std::string(token) + "'; expected a non-negative integer");
        }
        for (std::int64_t j = 0; j < items; ++j) {
          if (next_token(rest).empty()) {
            throw fail("line ends inside list '" + p.name + "' of " + std::to_string(items) + " items");
          }
        }
        continue;
      }
      const int b = layout.binding_of_property[k];
      if (b != kUnboundProperty && !store_text_value(token, layout.bindings[b], points, i, expected)) {
        throw fail("property '" + p.name + "' is '" + std::string(token) + "'; expected " + expected);
      }
    }
    if (!is_blank(rest)) {
      throw fail("more values than the " + std::to_string(vertex.properties.size()) +
                 " properties the header declares");
    }
  }
}

}  // namespace

PointBuffer read_ply(const std::filesystem::path& path, PointCloudFileInfo* info, const InputLimits& limits) {
  const std::string file = path.string();
  const FileBytes contents = read_file_bytes(path, limits.max_file_bytes);
  const std::string_view bytes = contents.view();
  const PlyHeader header = parse_ply_header(bytes, file);

  const auto vertex_it = std::find_if(header.elements.begin(), header.elements.end(),
                                      [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex_it == header.elements.end()) {
    throw Error(ErrorCode::Parse, at_line(file, header.header_lines, "header declares no 'element vertex'"));
  }
  const PlyElement& vertex = *vertex_it;
  const bool vertex_is_last = vertex_it + 1 == header.elements.end();
  VertexLayout layout = bind_vertex_properties(vertex, file);

  PointBuffer points;
  if (header.encoding == PlyEncoding::Ascii) {
    DataLines lines(bytes.substr(header.data_offset), header.header_lines);
    for (auto e = header.elements.begin(); e != vertex_it; ++e) skip_ascii_element(lines, *e, file);
    // A rough bound for the count check: bytes after the header.
    read_ascii_vertices(lines, bytes.size() - header.data_offset, vertex, layout, points, file, limits);
    std::string_view extra;
    if (vertex_is_last && lines.next_nonblank(extra)) {
      throw Error(ErrorCode::Parse, at_line(file, lines.line_number(),
                                            "data continues after the " + std::to_string(vertex.count) +
                                                " vertices the header declares (count wrong?)"));
    }
  } else {
    std::size_t offset = header.data_offset;
    for (auto e = header.elements.begin(); e != vertex_it; ++e) offset = skip_records(bytes, offset, *e, e->count, file);
    read_binary_vertices(bytes, offset, vertex, layout, points, file, limits);
    if (vertex_is_last) {
      const std::size_t end = skip_records(bytes, offset, vertex, vertex.count, file);
      if (end != bytes.size()) {
        throw Error(ErrorCode::Parse, at_offset(file, end, std::to_string(bytes.size() - end) +
                                                               " bytes follow the " + std::to_string(vertex.count) +
                                                               " vertices the header declares (count wrong?)"));
      }
    }
  }

  const std::size_t dropped = drop_non_finite(points);
  if (info != nullptr) {
    info->format = PointCloudFormat::Ply;
    info->encoding = std::string(to_string(header.encoding));
    info->fields.clear();
    for (const PlyProperty& p : vertex.properties) info->fields.push_back(p.name);
    info->points_in_file = static_cast<std::size_t>(vertex.count);
    info->dropped_non_finite = dropped;
    info->comments = header.comments;
  }
  return points;
}

}  // namespace sarmap
