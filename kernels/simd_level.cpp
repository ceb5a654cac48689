// Run-time choice of the kernels' instruction set (see simd_level.hpp).
#include "kernels/simd_level.hpp"

#include <atomic>
#include <cstdlib>

namespace sarmap::kernels {
namespace {

// Preference order when nothing is forced: measured, not by width (PERF.md).
constexpr SimdLevel kPreference[] = {SimdLevel::Avx512, SimdLevel::Avx2, SimdLevel::Sse42};

SimdLevel initial_level() {
  if (const char* forced = std::getenv("SARMAP_SIMD")) {
    if (auto level = simd_level_from_string(forced); level && simd_level_supported(*level)) return *level;
  }
  for (SimdLevel level : kPreference) {
    if (simd_level_supported(level)) return level;
  }
  return SimdLevel::Sse42;
}

std::atomic<int>& level_slot() {
  static std::atomic<int> slot{static_cast<int>(initial_level())};
  return slot;
}

}  // namespace

std::string_view to_string(SimdLevel level) {
  switch (level) {
    case SimdLevel::Sse42: return "sse4_2";
    case SimdLevel::Avx2: return "avx2";
    case SimdLevel::Avx512: return "avx512";
  }
  return "unknown";
}

std::optional<SimdLevel> simd_level_from_string(std::string_view name) {
  for (SimdLevel level : {SimdLevel::Sse42, SimdLevel::Avx2, SimdLevel::Avx512}) {
    if (to_string(level) == name) return level;
  }
  return std::nullopt;
}

bool simd_level_supported(SimdLevel level) {
  // GCC's CPU probe also checks that the OS saves the wide registers (XCR0),
  // which xsimd 8.1's cpuid probe does not.
  __builtin_cpu_init();
  switch (level) {
    case SimdLevel::Sse42: return __builtin_cpu_supports("sse4.2");
    case SimdLevel::Avx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case SimdLevel::Avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl");
  }
  return false;
}

SimdLevel active_simd_level() { return static_cast<SimdLevel>(level_slot().load(std::memory_order_relaxed)); }

bool set_simd_level(SimdLevel level) {
  if (!simd_level_supported(level)) return false;
  level_slot().store(static_cast<int>(level), std::memory_order_relaxed);
  return true;
}

int simd_lanes(SimdLevel level) {
  switch (level) {
    case SimdLevel::Sse42: return 4;
    case SimdLevel::Avx2: return 8;
    case SimdLevel::Avx512: return 16;
  }
  return 4;
}

}  // namespace sarmap::kernels
