// Reads PCD v0.7 point clouds (ascii, binary, binary_compressed) into a
// PointBuffer. Sizes declared by the header are checked against the file
// before any allocation; binary data is decoded column by column straight
// into the buffer's arrays (binary_compressed is already stored by column).
#include <cstring>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/field_binding.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/lzf.hpp"
#include "engine/io/pcd.hpp"
#include "engine/io/pcd_header.hpp"
#include "engine/io/text_parse.hpp"

namespace sarmap {
namespace {

constexpr int kUnboundField = -1;

struct FieldLayout {
  std::vector<FieldBinding> bindings;
  std::vector<int> binding_of_field;
};

FieldLayout bind_fields(const PcdHeader& header, const std::string& file) {
  FieldLayout layout;
  bool has[3] = {false, false, false};
  for (const PcdField& f : header.fields) {
    const auto attribute = attribute_from_pcd_name(f.name);
    if (!attribute) {
      layout.binding_of_field.push_back(kUnboundField);
      continue;
    }
    if (f.count != 1) {
      throw Error(ErrorCode::Parse, at_line(file, header.count_line, "field '" + f.name + "' has COUNT " +
                                                                         std::to_string(f.count) + "; expected 1"));
    }
    const std::string expected = expected_type_for(*attribute, f.type);
    if (!expected.empty()) {
      throw Error(ErrorCode::Parse, at_line(file, header.type_line,
                                            "field '" + f.name + "' has TYPE " + pcd_type_letter(f.type) +
                                                " SIZE " + std::to_string(scalar_size(f.type)) + "; expected " +
                                                expected));
    }
    if (*attribute <= PointAttribute::Z) has[static_cast<int>(*attribute)] = true;
    FieldBinding b;
    b.name = f.name;
    b.attribute = *attribute;
    b.type = f.type;
    if (*attribute == PointAttribute::Score) b.score_name = score_name_of(f.name);
    layout.binding_of_field.push_back(static_cast<int>(layout.bindings.size()));
    layout.bindings.push_back(std::move(b));
  }
  static constexpr const char* kAxes[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    if (!has[axis]) {
      throw Error(ErrorCode::Parse, at_line(file, header.fields_line, std::string("FIELDS has no '") + kAxes[axis] +
                                                                          "'; x, y and z are required"));
    }
  }
  return layout;
}

// After the reader's size check, whose error says more of a lying header.
void prepare(PointBuffer& points, const FieldLayout& layout, std::size_t count, const InputLimits& limits,
             const std::string& file) {
  check_declared_points(count, limits, file);
  points.resize(count);
  for (const FieldBinding& b : layout.bindings) enable_attribute(points, b);
}

[[noreturn]] void throw_bad_label(const std::string& where, const FieldBinding& b, std::size_t point,
                                  std::int64_t value) {
  throw Error(ErrorCode::InvalidData, where + "field '" + b.name + "' of point " + std::to_string(point) + " is " +
                                          std::to_string(value) + "; expected a class id in 0..255");
}

// PCL 1.13's binary writers leave zero bytes after the data (3906 after the
// 300 points of tests/data/clouds/pcl_tools_binary.pcd, 1389 after the
// compressed data of pcl_tools_binary_compressed.pcd), so zeros there are
// padding; anything else after the data is a wrong count or a damaged file.
void refuse_non_zero_after_data(std::string_view bytes, std::size_t data_end, const std::string& data,
                                const std::string& hint, const std::string& file) {
  const std::size_t non_zero = bytes.find_first_not_of('\0', data_end);
  if (non_zero == std::string_view::npos) return;
  throw Error(ErrorCode::Parse, at_offset(file, data_end,
                                          std::to_string(bytes.size() - data_end) + " bytes follow the " + data +
                                              " and the one at byte offset " + std::to_string(non_zero) +
                                              " is not zero (only zero padding may follow the data): " + hint));
}

void read_binary(std::string_view bytes, const PcdHeader& header, FieldLayout& layout, PointBuffer& points,
                 const std::string& file, const InputLimits& limits) {
  const std::size_t stride = header.point_size();
  const std::size_t offset = header.data_offset;
  const std::size_t remaining = bytes.size() - offset;
  if (header.points > remaining / stride) {
    throw Error(ErrorCode::Parse, at_offset(file, offset, "header declares " + std::to_string(header.points) +
                                                              " points of " + std::to_string(stride) +
                                                              " bytes but only " + std::to_string(remaining) +
                                                              " bytes of data follow (file truncated or POINTS wrong)"));
  }
  const auto count = static_cast<std::size_t>(header.points);
  refuse_non_zero_after_data(bytes, offset + count * stride, std::to_string(count) + " points the header declares",
                             "POINTS wrong?", file);
  std::size_t field_offset = 0;
  for (std::size_t k = 0; k < header.fields.size(); ++k) {
    if (layout.binding_of_field[k] != kUnboundField) {
      FieldBinding& b = layout.bindings[layout.binding_of_field[k]];
      b.offset = field_offset;
      b.stride = stride;
    }
    field_offset += header.fields[k].bytes();
  }
  prepare(points, layout, count, limits, file);
  if (const auto failure = decode_binary_fields(bytes.data() + offset, count, layout.bindings, points, 0)) {
    const FieldBinding& b = layout.bindings[failure->binding];
    throw_bad_label(at_offset(file, offset + failure->point * stride + b.offset, ""), b, failure->point,
                    failure->value);
  }
}

std::uint32_t load_u32(const char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

void read_binary_compressed(std::string_view bytes, const PcdHeader& header, FieldLayout& layout,
                            PointBuffer& points, const std::string& file, const InputLimits& limits) {
  const std::size_t offset = header.data_offset;
  if (bytes.size() - offset < 8) {
    throw Error(ErrorCode::Parse, at_offset(file, offset, "file ends before the binary_compressed sizes "
                                                          "(two uint32: compressed, uncompressed)"));
  }
  const std::uint32_t compressed_size = load_u32(bytes.data() + offset);
  const std::uint32_t uncompressed_size = load_u32(bytes.data() + offset + 4);
  const std::size_t stride = header.point_size();
  // Overflow-safe: a declared count whose data cannot fit 32 bits is a lie.
  if (header.points > UINT32_MAX / stride || header.points * stride != uncompressed_size) {
    throw Error(ErrorCode::Parse,
                at_offset(file, offset + 4, "uncompressed size is " + std::to_string(uncompressed_size) +
                                                " bytes; expected POINTS * point size = " +
                                                std::to_string(header.points) + " * " + std::to_string(stride)));
  }
  const std::size_t data = offset + 8;
  if (compressed_size > bytes.size() - data) {
    throw Error(ErrorCode::Parse, at_offset(file, data, "compressed size is " + std::to_string(compressed_size) +
                                                            " bytes but only " + std::to_string(bytes.size() - data) +
                                                            " bytes follow (file truncated?)"));
  }
  if (uncompressed_size > lzf_max_decompressed_size(compressed_size)) {
    throw Error(ErrorCode::Parse, at_offset(file, offset, std::to_string(compressed_size) +
                                                              " compressed bytes cannot expand to the declared " +
                                                              std::to_string(uncompressed_size)));
  }
  refuse_non_zero_after_data(bytes, data + compressed_size,
                             std::to_string(compressed_size) + " compressed bytes the file declares",
                             "compressed size wrong?", file);
  const auto count = static_cast<std::size_t>(header.points);
  std::vector<std::uint8_t> unpacked(uncompressed_size);
  try {
    lzf_decompress({reinterpret_cast<const std::uint8_t*>(bytes.data() + data), compressed_size}, unpacked);
  } catch (const Error& e) {
    throw Error(ErrorCode::Parse, at_offset(file, data, e.what()));
  }
  // Stored by field: all values of the first field, then the second, ...
  std::size_t column = 0;
  for (std::size_t k = 0; k < header.fields.size(); ++k) {
    if (layout.binding_of_field[k] != kUnboundField) {
      FieldBinding& b = layout.bindings[layout.binding_of_field[k]];
      b.offset = column;
      b.stride = header.fields[k].bytes();
    }
    column += header.fields[k].bytes() * count;
  }
  prepare(points, layout, count, limits, file);
  const char* base = reinterpret_cast<const char*>(unpacked.data());
  if (const auto failure = decode_binary_fields(base, count, layout.bindings, points, 0)) {
    const FieldBinding& b = layout.bindings[failure->binding];
    const std::size_t at = b.offset + failure->point * b.stride;
    throw_bad_label(at_offset(file, data, "decompressed byte " + std::to_string(at) + ": "), b, failure->point,
                    failure->value);
  }
}

void read_ascii(std::string_view bytes, const PcdHeader& header, const FieldLayout& layout, PointBuffer& points,
                const std::string& file, const InputLimits& limits) {
  std::size_t values = 0;
  for (const PcdField& f : header.fields) values += f.count;
  const std::size_t remaining = bytes.size() - header.data_offset;
  // Each value takes at least one character and one separator.
  if (header.points > (remaining + 1) / (2 * values)) {
    throw Error(ErrorCode::Parse, at_line(file, header.points_line,
                                          "header declares " + std::to_string(header.points) + " points but only " +
                                              std::to_string(remaining) + " bytes of data follow (at least " +
                                              std::to_string(2 * values) +
                                              " per point): file truncated or POINTS wrong"));
  }
  const auto count = static_cast<std::size_t>(header.points);
  prepare(points, layout, count, limits, file);
  LineReader lines(bytes.substr(header.data_offset));
  auto line_number = [&] { return header.header_lines + lines.line_number(); };
  std::string_view line;
  auto next_nonblank = [&] {
    while (lines.next(line)) {
      if (!is_blank(line)) return true;
    }
    return false;
  };
  std::string expected;
  for (std::size_t i = 0; i < count; ++i) {
    if (!next_nonblank()) {
      throw Error(ErrorCode::Parse, at_line(file, line_number(), "file ends after " + std::to_string(i) + " of the " +
                                                                     std::to_string(count) +
                                                                     " points the header declares"));
    }
    auto fail = [&](const std::string& what) {
      return Error(ErrorCode::Parse, at_line(file, line_number(), "point " + std::to_string(i) + ": " + what));
    };
    std::string_view rest = line;
    for (std::size_t k = 0; k < header.fields.size(); ++k) {
      const PcdField& f = header.fields[k];
      const int b = layout.binding_of_field[k];
      for (std::size_t c = 0; c < f.count; ++c) {
        const std::string_view token = next_token(rest);
        if (token.empty()) {
          throw fail("line ends before field '" + f.name + "' (expected " + std::to_string(values) +
                     " values per line)");
        }
        if (b != kUnboundField && !store_text_value(token, layout.bindings[b], points, i, expected)) {
          throw fail("field '" + f.name + "' is '" + std::string(token) + "'; expected " + expected);
        }
      }
    }
    if (!is_blank(rest)) throw fail("more than the " + std::to_string(values) + " values the header declares");
  }
  if (next_nonblank()) {
    throw Error(ErrorCode::Parse, at_line(file, line_number(), "data continues after the " + std::to_string(count) +
                                                                   " points the header declares (POINTS wrong?)"));
  }
}

}  // namespace

PointBuffer read_pcd(const std::filesystem::path& path, PointCloudFileInfo* info, const InputLimits& limits) {
  const std::string file = path.string();
  const FileBytes contents = read_file_bytes(path, limits.max_file_bytes);
  const std::string_view bytes = contents.view();
  const PcdHeader header = parse_pcd_header(bytes, file);
  FieldLayout layout = bind_fields(header, file);

  PointBuffer points;
  switch (header.encoding) {
    case PcdEncoding::Ascii: read_ascii(bytes, header, layout, points, file, limits); break;
    case PcdEncoding::Binary: read_binary(bytes, header, layout, points, file, limits); break;
    case PcdEncoding::BinaryCompressed: read_binary_compressed(bytes, header, layout, points, file, limits); break;
  }
  const std::size_t dropped = drop_non_finite(points);
  if (info != nullptr) {
    info->format = PointCloudFormat::Pcd;
    info->encoding = std::string(to_string(header.encoding));
    info->fields.clear();
    for (const PcdField& f : header.fields) info->fields.push_back(f.name);
    info->points_in_file = static_cast<std::size_t>(header.points);
    info->dropped_non_finite = dropped;
    info->comments = header.comments;
  }
  return points;
}

}  // namespace sarmap
