// Bounds of the kNN kernel's per-row state, which lives on the stack so the
// kernel never allocates: k neighbours of points of at most kKnnMaxDim floats.
#pragma once

#include <cstddef>

namespace sarmap::kernels {

inline constexpr std::size_t kKnnMaxK = 64;
inline constexpr std::size_t kKnnMaxDim = 256;

}  // namespace sarmap::kernels
