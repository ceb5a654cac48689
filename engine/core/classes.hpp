// The semantic classes sarmap maps, with their names and display colours, as
// one table shared by every reader, writer, viewer and evaluator.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace sarmap {

enum class ClassId : std::uint8_t {
  Unknown = 0,
  Terrain = 1,
  Wall = 2,
  InclinedRamp = 3,
  FlatRamp = 4,
  Other = 5,
};

inline constexpr std::size_t kClassCount = 6;

struct Rgb {
  std::uint8_t r, g, b;
  friend bool operator==(Rgb, Rgb) = default;
};

struct ClassInfo {
  ClassId id;
  std::string_view name;  // machine name used in files: "inclined_ramp"
  std::string_view display_name;
  Rgb color;  // follows the papers' figures
};

// Indexed by class id.
inline constexpr std::array<ClassInfo, kClassCount> kClassTable{{
    {ClassId::Unknown, "unknown", "unknown", {0, 0, 0}},
    {ClassId::Terrain, "terrain", "terrain", {230, 200, 20}},            // yellow
    {ClassId::Wall, "wall", "wall", {220, 30, 30}},                       // red
    {ClassId::InclinedRamp, "inclined_ramp", "inclined ramp", {30, 80, 230}},  // blue
    {ClassId::FlatRamp, "flat_ramp", "flat ramp", {200, 60, 200}},        // pink / purple
    {ClassId::Other, "other", "other", {140, 140, 140}},                  // grey
}};

constexpr const ClassInfo& class_info(ClassId id) {
  return kClassTable[static_cast<std::size_t>(id)];
}

// Returns nullopt for a raw value that is not a class id.
constexpr std::optional<ClassId> class_from_value(unsigned value) {
  if (value >= kClassCount) return std::nullopt;
  return static_cast<ClassId>(value);
}

// Accepts the machine name ("flat_ramp"); nullopt for anything else.
constexpr std::optional<ClassId> class_from_name(std::string_view name) {
  for (const ClassInfo& info : kClassTable) {
    if (info.name == name) return info.id;
  }
  return std::nullopt;
}

}  // namespace sarmap
