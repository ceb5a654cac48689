// The numeric types a point-cloud file can store per value (PLY's char..double,
// PCD's I/U/F with SIZE 1..8), shared by the PLY and PCD readers so both decode
// columns with the same code.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace sarmap {

enum class ScalarType : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

std::size_t scalar_size(ScalarType type);
bool is_integer(ScalarType type);
// PLY spelling ("uchar", "float", ...) of the type.
std::string_view ply_type_name(ScalarType type);
// Accepts both PLY spellings: "uchar" and "uint8", "float" and "float32", ...
// (PLY has no 64-bit integers).
std::optional<ScalarType> scalar_type_from_ply(std::string_view name);
// PCD TYPE letter (I, U, F) with SIZE in bytes; nullopt for combinations that
// do not exist (F 2, U 3, ...).
std::optional<ScalarType> scalar_type_from_pcd(char type, std::size_t size);
char pcd_type_letter(ScalarType type);

}  // namespace sarmap
