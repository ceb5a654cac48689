// Which instruction set the kernels run with. Every kernel is compiled for
// SSE4.2 (the build baseline), AVX2+FMA and AVX-512 and picked at run time, so
// one binary runs on any x86-64 with SSE4.2; tests and benchmarks force a level.
#pragma once

#include <optional>
#include <string_view>

namespace sarmap::kernels {

enum class SimdLevel { Sse42 = 0, Avx2 = 1, Avx512 = 2 };

std::string_view to_string(SimdLevel level);
std::optional<SimdLevel> simd_level_from_string(std::string_view name);

// Whether this CPU (and OS) can run a level.
bool simd_level_supported(SimdLevel level);

// The level the kernels use: the preferred supported one unless forced with
// set_simd_level() or the SARMAP_SIMD environment variable (sse4_2, avx2, avx512).
// Preference by measurement (bench/kernels, bench/semantic): on every
// machine with both that sarmap has been measured on, the AVX-512 kernels
// beat the AVX2 ones in the same run (PERF.md).
SimdLevel active_simd_level();

// Forces a level for the whole process; returns false (and changes nothing)
// when the CPU cannot run it. Not thread-safe against running kernels.
bool set_simd_level(SimdLevel level);

// Vector width in floats, the GEMM panel width (two vectors) and the row tile
// height of each level; packed weights are laid out for one level.
int simd_lanes(SimdLevel level);
inline int panel_width(SimdLevel level) { return 2 * simd_lanes(level); }

}  // namespace sarmap::kernels
