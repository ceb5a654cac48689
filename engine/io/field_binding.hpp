// Binds a field of a point-cloud file (a PLY property or a PCD field) to the
// PointBuffer array it fills, and decodes binary columns of such fields
// straight into those arrays. Shared by the PLY and PCD readers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "engine/core/point_buffer.hpp"
#include "engine/io/scalar_type.hpp"

namespace sarmap {

enum class PointAttribute : std::uint8_t {
  X, Y, Z,
  NormalX, NormalY, NormalZ,
  Intensity,
  Score,      // a named float channel (PLY scalar_<name>)
  Red, Green, Blue,
  PackedRgb,  // PCD rgb/rgba: 0x00RRGGBB in 4 bytes (U 4, or F 4 read as bits)
  Label, GtLabel,
};

// A file field that sarmap keeps. Fields that are not bound are skipped.
struct FieldBinding {
  std::string name;  // as written in the file
  PointAttribute attribute = PointAttribute::X;
  ScalarType type = ScalarType::Float32;
  std::string score_name;  // for PointAttribute::Score: the channel name
  // Binary layout: the value of point i is at data + offset + i * stride.
  std::size_t offset = 0;
  std::size_t stride = 0;
  // ASCII layout: index of the value within a point's line.
  std::size_t token = 0;
};

// The attribute a PLY-style / PCD-style name maps to (x, nx / normal_x, red,
// rgb, label, gt_label, intensity, scalar_<name>); nullopt for a field that is skipped.
std::optional<PointAttribute> attribute_from_ply_name(std::string_view name);
std::optional<PointAttribute> attribute_from_pcd_name(std::string_view name);
// "scalar_height" -> "height"; used for PointAttribute::Score names.
std::string score_name_of(std::string_view field_name);

// Empty when the type can hold the attribute; otherwise what was expected,
// e.g. "float or double" (coordinates), "uchar" (colours), "an integer type" (labels).
std::string expected_type_for(PointAttribute attribute, ScalarType type);

// Enables the attribute's arrays on points (which must already have its final
// size) and records the score channel for Score bindings.
void enable_attribute(PointBuffer& points, const FieldBinding& binding);

// A value that cannot be stored: a label outside 0..255.
struct DecodeFailure {
  std::size_t binding = 0;  // index into the bindings
  std::size_t point = 0;    // index of the point (relative to the decoded range)
  std::int64_t value = 0;
};

// Decodes points [0, count) of every binding from data (see FieldBinding's
// layout) into points [first, first + count). Cache-friendly: walks the
// records in blocks so every column of a block is decoded while it is hot.
std::optional<DecodeFailure> decode_binary_fields(const char* data, std::size_t count,
                                                  std::span<const FieldBinding> bindings, PointBuffer& points,
                                                  std::size_t first);

// Drops points whose x, y or z is NaN or infinite and returns how many. A
// branch-free scan first, so the common all-finite cloud costs one pass.
std::size_t drop_non_finite(PointBuffer& points);

// A point's values as text tokens, parsed for one binding and stored at index
// point. Returns false when the token is not a number of the binding's type or
// does not fit (a label outside 0..255); what_failed then says what was expected.
bool store_text_value(std::string_view token, const FieldBinding& binding, PointBuffer& points,
                      std::size_t point, std::string& what_failed);

}  // namespace sarmap
