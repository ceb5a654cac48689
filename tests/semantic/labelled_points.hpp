// Hand-made labelled point sets for the label-correcting rules' tests:
// points added one by one with a class label, and counted by label.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "engine/core/classes.hpp"
#include "engine/core/point_buffer.hpp"

namespace sarmap::testing {

inline constexpr auto kOther = static_cast<std::uint8_t>(ClassId::Other);
inline constexpr auto kWall = static_cast<std::uint8_t>(ClassId::Wall);
inline constexpr auto kTerrain = static_cast<std::uint8_t>(ClassId::Terrain);
inline constexpr auto kInclined = static_cast<std::uint8_t>(ClassId::InclinedRamp);
inline constexpr auto kFlat = static_cast<std::uint8_t>(ClassId::FlatRamp);

// An empty buffer that carries labels.
inline PointBuffer labelled() {
  PointBuffer points;
  points.enable_labels();
  return points;
}

inline void add(PointBuffer& points, double x, double y, double z, std::uint8_t label) {
  points.push_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
  points.labels().back() = label;
}

inline std::size_t count(const PointBuffer& points, std::uint8_t label) {
  return static_cast<std::size_t>(std::count(points.labels().begin(), points.labels().end(), label));
}

}  // namespace sarmap::testing
