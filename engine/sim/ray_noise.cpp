#include "engine/sim/ray_noise.hpp"

#include <cmath>
#include <numbers>

namespace sarmap::sim {

double uniform01(std::uint64_t key, std::uint64_t stream) {
  // 53 random bits fill a double's mantissa exactly.
  return static_cast<double>(mix64(key ^ (stream * 0xD1B54A32D192ED03ull)) >> 11) * 0x1.0p-53;
}

double standard_normal(std::uint64_t key) {
  const double u1 = 1.0 - uniform01(key, 1);  // (0, 1]: log stays finite
  const double u2 = uniform01(key, 2);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

double kinect_sigma(double depth) {
  const double d = depth - 0.4;
  return 0.0012 + 0.0019 * d * d;
}

bool apply_noise(const NoiseSpec& noise, double value, std::uint64_t key, double& measured) {
  if (noise.dropout > 0 && uniform01(key, 3) < noise.dropout) return false;
  switch (noise.kind) {
    case NoiseKind::None: measured = value; break;
    case NoiseKind::Gaussian: measured = value + noise.sigma * standard_normal(key); break;
    case NoiseKind::Kinect: measured = value + kinect_sigma(value) * standard_normal(key); break;
  }
  return true;
}

}  // namespace sarmap::sim
