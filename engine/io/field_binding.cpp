#include "engine/io/field_binding.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <type_traits>

#include "engine/io/text_parse.hpp"

namespace sarmap {

// Binary values are copied as the host stores them; both formats sarmap reads
// in binary are little-endian.
static_assert(std::endian::native == std::endian::little, "binary point-cloud decoding assumes a little-endian host");

namespace {

constexpr std::string_view kScorePrefix = "scalar_";

bool is_float_attribute(PointAttribute a) {
  return a == PointAttribute::X || a == PointAttribute::Y || a == PointAttribute::Z ||
         a == PointAttribute::NormalX || a == PointAttribute::NormalY || a == PointAttribute::NormalZ ||
         a == PointAttribute::Intensity || a == PointAttribute::Score;
}

template <class T>
struct TypeTag {
  using type = T;
};

template <class Fn>
decltype(auto) with_scalar_type(ScalarType type, Fn&& fn) {
  switch (type) {
    case ScalarType::Int8: return fn(TypeTag<std::int8_t>{});
    case ScalarType::UInt8: return fn(TypeTag<std::uint8_t>{});
    case ScalarType::Int16: return fn(TypeTag<std::int16_t>{});
    case ScalarType::UInt16: return fn(TypeTag<std::uint16_t>{});
    case ScalarType::Int32: return fn(TypeTag<std::int32_t>{});
    case ScalarType::UInt32: return fn(TypeTag<std::uint32_t>{});
    case ScalarType::Int64: return fn(TypeTag<std::int64_t>{});
    case ScalarType::UInt64: return fn(TypeTag<std::uint64_t>{});
    case ScalarType::Float32: return fn(TypeTag<float>{});
    case ScalarType::Float64: break;
  }
  return fn(TypeTag<double>{});
}

template <class T>
T load(const char* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

// The array a binding writes into, resolved once per read.
struct Target {
  float* f = nullptr;
  std::uint8_t* u8 = nullptr;
  std::uint8_t* green = nullptr;  // PackedRgb only (u8 is red)
  std::uint8_t* blue = nullptr;
};

Target resolve(PointBuffer& points, const FieldBinding& b) {
  switch (b.attribute) {
    case PointAttribute::X: return {points.x().data()};
    case PointAttribute::Y: return {points.y().data()};
    case PointAttribute::Z: return {points.z().data()};
    case PointAttribute::NormalX: return {points.normal_x().data()};
    case PointAttribute::NormalY: return {points.normal_y().data()};
    case PointAttribute::NormalZ: return {points.normal_z().data()};
    case PointAttribute::Intensity: return {points.intensity().data()};
    case PointAttribute::Score: return {points.score(points.find_score(b.score_name)).data()};
    case PointAttribute::Red: return {nullptr, points.red().data()};
    case PointAttribute::Green: return {nullptr, points.green().data()};
    case PointAttribute::Blue: return {nullptr, points.blue().data()};
    case PointAttribute::PackedRgb:
      return {nullptr, points.red().data(), points.green().data(), points.blue().data()};
    case PointAttribute::Label: return {nullptr, points.labels().data()};
    case PointAttribute::GtLabel: return {nullptr, points.gt_labels().data()};
  }
  return {};
}

void split_rgb(std::uint32_t packed, const Target& t, std::size_t i) {
  t.u8[i] = static_cast<std::uint8_t>(packed >> 16);
  t.green[i] = static_cast<std::uint8_t>(packed >> 8);
  t.blue[i] = static_cast<std::uint8_t>(packed);
}

// Decodes one column of n values; returns the index of the first label that
// does not fit a byte, or n.
std::size_t decode_column(const char* src, std::size_t stride, std::size_t n, const FieldBinding& b,
                          const Target& t, std::size_t first) {
  if (is_float_attribute(b.attribute)) {
    with_scalar_type(b.type, [&](auto tag) {
      using T = typename decltype(tag)::type;
      float* dst = t.f + first;
      for (std::size_t i = 0; i < n; ++i) dst[i] = static_cast<float>(load<T>(src + i * stride));
    });
    return n;
  }
  if (b.attribute == PointAttribute::PackedRgb) {
    for (std::size_t i = 0; i < n; ++i) split_rgb(load<std::uint32_t>(src + i * stride), t, first + i);
    return n;
  }
  // Colours (uchar only) and labels (any integer type, checked to fit a byte).
  return with_scalar_type(b.type, [&](auto tag) -> std::size_t {
    using T = typename decltype(tag)::type;
    std::uint8_t* dst = t.u8 + first;
    if constexpr (std::is_same_v<T, std::uint8_t>) {
      for (std::size_t i = 0; i < n; ++i) dst[i] = static_cast<std::uint8_t>(src[i * stride]);
    } else if constexpr (std::is_integral_v<T>) {
      for (std::size_t i = 0; i < n; ++i) {
        const T v = load<T>(src + i * stride);
        bool fits = true;
        if constexpr (std::is_signed_v<T>) fits = v >= 0;
        if constexpr (sizeof(T) > 1 || std::is_unsigned_v<T>) fits = fits && static_cast<std::uint64_t>(v) <= 255;
        if (!fits) return i;
        dst[i] = static_cast<std::uint8_t>(v);
      }
    } else {
      return 0;  // expected_type_for() rejects floating-point labels before decoding
    }
    return n;
  });
}

std::int64_t raw_integer(const char* p, ScalarType type) {
  return with_scalar_type(type, [p](auto tag) {
    using T = typename decltype(tag)::type;
    return static_cast<std::int64_t>(load<T>(p));
  });
}

}  // namespace

std::optional<PointAttribute> attribute_from_ply_name(std::string_view name) {
  if (name == "x") return PointAttribute::X;
  if (name == "y") return PointAttribute::Y;
  if (name == "z") return PointAttribute::Z;
  if (name == "nx") return PointAttribute::NormalX;
  if (name == "ny") return PointAttribute::NormalY;
  if (name == "nz") return PointAttribute::NormalZ;
  if (name == "red") return PointAttribute::Red;
  if (name == "green") return PointAttribute::Green;
  if (name == "blue") return PointAttribute::Blue;
  if (name == "intensity") return PointAttribute::Intensity;
  if (name == "label") return PointAttribute::Label;
  if (name == "gt_label") return PointAttribute::GtLabel;
  if (name.size() > kScorePrefix.size() && name.starts_with(kScorePrefix)) return PointAttribute::Score;
  return std::nullopt;
}

std::optional<PointAttribute> attribute_from_pcd_name(std::string_view name) {
  if (name == "x") return PointAttribute::X;
  if (name == "y") return PointAttribute::Y;
  if (name == "z") return PointAttribute::Z;
  if (name == "normal_x") return PointAttribute::NormalX;
  if (name == "normal_y") return PointAttribute::NormalY;
  if (name == "normal_z") return PointAttribute::NormalZ;
  if (name == "rgb" || name == "rgba") return PointAttribute::PackedRgb;
  if (name == "intensity") return PointAttribute::Intensity;
  if (name == "label") return PointAttribute::Label;
  if (name == "gt_label") return PointAttribute::GtLabel;
  if (name.size() > kScorePrefix.size() && name.starts_with(kScorePrefix)) return PointAttribute::Score;
  return std::nullopt;
}

std::string score_name_of(std::string_view field_name) {
  if (field_name.starts_with(kScorePrefix)) field_name.remove_prefix(kScorePrefix.size());
  return std::string(field_name);
}

std::string expected_type_for(PointAttribute attribute, ScalarType type) {
  switch (attribute) {
    case PointAttribute::Intensity: return {};  // any numeric type (LiDARs store ushort)
    case PointAttribute::Red:
    case PointAttribute::Green:
    case PointAttribute::Blue: return type == ScalarType::UInt8 ? std::string() : "uchar (8-bit colour)";
    case PointAttribute::PackedRgb:
      return type == ScalarType::UInt32 || type == ScalarType::Int32 || type == ScalarType::Float32
                 ? std::string()
                 : "4-byte packed 0x00RRGGBB (U 4, or F 4 as PCL writes it)";
    case PointAttribute::Label:
    case PointAttribute::GtLabel: return is_integer(type) ? std::string() : "an integer type (class id)";
    default: return is_integer(type) ? "float or double" : std::string();
  }
}

void enable_attribute(PointBuffer& points, const FieldBinding& binding) {
  switch (binding.attribute) {
    case PointAttribute::X:
    case PointAttribute::Y:
    case PointAttribute::Z: return;
    case PointAttribute::NormalX:
    case PointAttribute::NormalY:
    case PointAttribute::NormalZ: points.enable_normals(); return;
    case PointAttribute::Intensity: points.enable_intensity(); return;
    case PointAttribute::Score: points.add_score(binding.score_name); return;
    case PointAttribute::Red:
    case PointAttribute::Green:
    case PointAttribute::Blue:
    case PointAttribute::PackedRgb: points.enable_colors(); return;
    case PointAttribute::Label: points.enable_labels(); return;
    case PointAttribute::GtLabel: points.enable_gt_labels(); return;
  }
}

std::optional<DecodeFailure> decode_binary_fields(const char* data, std::size_t count,
                                                  std::span<const FieldBinding> bindings, PointBuffer& points,
                                                  std::size_t first) {
  // A block of records small enough to stay in L1/L2 while each of its
  // columns is decoded, so the file is streamed from memory once.
  constexpr std::size_t kBlock = 2048;
  std::vector<Target> targets;
  targets.reserve(bindings.size());
  for (const FieldBinding& b : bindings) targets.push_back(resolve(points, b));
  for (std::size_t start = 0; start < count; start += kBlock) {
    const std::size_t n = std::min(kBlock, count - start);
    for (std::size_t k = 0; k < bindings.size(); ++k) {
      const FieldBinding& b = bindings[k];
      const char* src = data + b.offset + start * b.stride;
      const std::size_t ok = decode_column(src, b.stride, n, b, targets[k], first + start);
      if (ok < n) return DecodeFailure{k, start + ok, raw_integer(src + ok * b.stride, b.type)};
    }
  }
  return std::nullopt;
}

std::size_t drop_non_finite(PointBuffer& points) {
  const float* x = points.x().data();
  const float* y = points.y().data();
  const float* z = points.z().data();
  // An IEEE float is NaN or infinite exactly when all its exponent bits are set.
  constexpr std::uint32_t kExponent = 0x7f800000u;
  std::uint32_t non_finite = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    non_finite |= static_cast<std::uint32_t>((std::bit_cast<std::uint32_t>(x[i]) & kExponent) == kExponent) |
                  static_cast<std::uint32_t>((std::bit_cast<std::uint32_t>(y[i]) & kExponent) == kExponent) |
                  static_cast<std::uint32_t>((std::bit_cast<std::uint32_t>(z[i]) & kExponent) == kExponent);
  }
  return non_finite != 0 ? points.remove_non_finite() : 0;
}

bool store_text_value(std::string_view token, const FieldBinding& b, PointBuffer& points, std::size_t point,
                      std::string& what_failed) {
  const Target t = resolve(points, b);
  if (is_float_attribute(b.attribute)) {
    bool ok = false;
    if (is_integer(b.type)) {
      std::int64_t v = 0;
      ok = parse_number(token, v);
      t.f[point] = static_cast<float>(v);
    } else if (b.type == ScalarType::Float32) {
      ok = parse_number(token, t.f[point]);
    } else {
      double v = 0;
      ok = parse_number(token, v);
      t.f[point] = static_cast<float>(v);
    }
    if (!ok) what_failed = is_integer(b.type) ? "an integer" : "a number";
    return ok;
  }
  if (b.attribute == PointAttribute::PackedRgb) {
    // PCL writes rgb as the decimal of its 32 bits even when TYPE is F, but
    // other writers print the float itself: take an integer as bits, a float
    // as a float whose bits are the colour.
    std::uint64_t bits = 0;
    if (parse_number(token, bits) && bits <= 0xffffffffu) {
      split_rgb(static_cast<std::uint32_t>(bits), t, point);
      return true;
    }
    float f = 0;
    if (b.type == ScalarType::Float32 && parse_number(token, f)) {
      split_rgb(std::bit_cast<std::uint32_t>(f), t, point);
      return true;
    }
    what_failed = "a packed rgb value (unsigned 32-bit integer)";
    return false;
  }
  std::int64_t v = 0;
  if (!parse_number(token, v)) {
    what_failed = "an integer";
    return false;
  }
  if (v < 0 || v > 255) {
    what_failed = b.attribute == PointAttribute::Label || b.attribute == PointAttribute::GtLabel
                      ? "a class id in 0..255"
                      : "a colour value in 0..255";
    return false;
  }
  t.u8[point] = static_cast<std::uint8_t>(v);
  return true;
}

}  // namespace sarmap
