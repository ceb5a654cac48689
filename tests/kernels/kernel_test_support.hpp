// Helpers shared by the kernel tests: seeded random arrays and the list of
// instruction sets this CPU can run (every kernel is checked at each).
#pragma once

#include <cstddef>
#include <random>
#include <vector>

#include "kernels/simd_level.hpp"

namespace sarmap::kernels::test {

inline std::vector<float> random_floats(std::size_t n, unsigned seed, float lo = -1.0f, float hi = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(lo, hi);
  std::vector<float> v(n);
  for (float& x : v) x = dist(rng);
  return v;
}

inline std::vector<SimdLevel> supported_levels() {
  std::vector<SimdLevel> levels;
  for (SimdLevel level : {SimdLevel::Sse42, SimdLevel::Avx2, SimdLevel::Avx512}) {
    if (simd_level_supported(level)) levels.push_back(level);
  }
  return levels;
}

}  // namespace sarmap::kernels::test
