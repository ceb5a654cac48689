// Radians per degree: angles in configs and arenas are in degrees, the
// maths in radians (`15 * kDeg`).
#pragma once

#include <numbers>

namespace sarmap {

inline constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace sarmap
