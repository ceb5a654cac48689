#include "engine/io/scalar_type.hpp"

namespace sarmap {

std::size_t scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
    case ScalarType::UInt8: return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16: return 2;
    case ScalarType::Int32:
    case ScalarType::UInt32:
    case ScalarType::Float32: return 4;
    case ScalarType::Int64:
    case ScalarType::UInt64:
    case ScalarType::Float64: return 8;
  }
  return 0;
}

bool is_integer(ScalarType type) { return type != ScalarType::Float32 && type != ScalarType::Float64; }

std::string_view ply_type_name(ScalarType type) {
  switch (type) {
    case ScalarType::Int8: return "char";
    case ScalarType::UInt8: return "uchar";
    case ScalarType::Int16: return "short";
    case ScalarType::UInt16: return "ushort";
    case ScalarType::Int32: return "int";
    case ScalarType::UInt32: return "uint";
    case ScalarType::Int64: return "int64";
    case ScalarType::UInt64: return "uint64";
    case ScalarType::Float32: return "float";
    case ScalarType::Float64: return "double";
  }
  return "?";
}

std::optional<ScalarType> scalar_type_from_ply(std::string_view name) {
  struct Entry {
    std::string_view a, b;
    ScalarType type;
  };
  static constexpr Entry kTable[] = {
      {"char", "int8", ScalarType::Int8},        {"uchar", "uint8", ScalarType::UInt8},
      {"short", "int16", ScalarType::Int16},     {"ushort", "uint16", ScalarType::UInt16},
      {"int", "int32", ScalarType::Int32},       {"uint", "uint32", ScalarType::UInt32},
      {"float", "float32", ScalarType::Float32}, {"double", "float64", ScalarType::Float64},
  };
  for (const Entry& e : kTable) {
    if (name == e.a || name == e.b) return e.type;
  }
  return std::nullopt;
}

std::optional<ScalarType> scalar_type_from_pcd(char type, std::size_t size) {
  switch (type) {
    case 'I':
      if (size == 1) return ScalarType::Int8;
      if (size == 2) return ScalarType::Int16;
      if (size == 4) return ScalarType::Int32;
      if (size == 8) return ScalarType::Int64;
      return std::nullopt;
    case 'U':
      if (size == 1) return ScalarType::UInt8;
      if (size == 2) return ScalarType::UInt16;
      if (size == 4) return ScalarType::UInt32;
      if (size == 8) return ScalarType::UInt64;
      return std::nullopt;
    case 'F':
      if (size == 4) return ScalarType::Float32;
      if (size == 8) return ScalarType::Float64;
      return std::nullopt;
    default: return std::nullopt;
  }
}

char pcd_type_letter(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
    case ScalarType::Int16:
    case ScalarType::Int32:
    case ScalarType::Int64: return 'I';
    case ScalarType::UInt8:
    case ScalarType::UInt16:
    case ScalarType::UInt32:
    case ScalarType::UInt64: return 'U';
    case ScalarType::Float32:
    case ScalarType::Float64: return 'F';
  }
  return '?';
}

}  // namespace sarmap
