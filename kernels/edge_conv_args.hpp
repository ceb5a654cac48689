// What the dispatching code hands a per-instruction-set EdgeConv kernel
// (internal to kernels/).
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/packed_matrix.hpp"

namespace sarmap::kernels::detail {

struct EdgeConvArgs {
  const float* a = nullptr;  // count x hidden: neighbour term, row stride ld_ab
  const float* b = nullptr;  // count x hidden: centre term (with the first bias)
  std::size_t ld_ab = 0;
  std::size_t count = 0;
  std::size_t hidden = 0;
  const std::uint32_t* idx = nullptr;  // count x k
  std::size_t k = 0;
  float slope1 = 1.0f;
  const PackedMatrix* w2 = nullptr;  // nullptr: gather-max only
  float slope2 = 1.0f;
  float* out = nullptr;  // count x (w2 ? w2->rows() : hidden), row stride ldo
  std::size_t ldo = 0;
};

// Points [begin, end).
using EdgeConvPointsFn = void (*)(const EdgeConvArgs&, std::size_t begin, std::size_t end);

void edge_conv_points_sse42(const EdgeConvArgs&, std::size_t, std::size_t);
void edge_conv_points_avx2(const EdgeConvArgs&, std::size_t, std::size_t);
void edge_conv_points_avx512(const EdgeConvArgs&, std::size_t, std::size_t);
void gather_max_points_sse42(const EdgeConvArgs&, std::size_t, std::size_t);
void gather_max_points_avx2(const EdgeConvArgs&, std::size_t, std::size_t);
void gather_max_points_avx512(const EdgeConvArgs&, std::size_t, std::size_t);

}  // namespace sarmap::kernels::detail
