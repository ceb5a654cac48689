// What the dispatching code hands a per-instruction-set GEMM: one struct, so
// the three compiled variants share one signature (internal to kernels/).
#pragma once

#include <cstddef>

#include "kernels/packed_matrix.hpp"

namespace sarmap::kernels::detail {

struct GemmArgs {
  const float* x = nullptr;  // m x w->cols(), row stride ldx
  std::size_t ldx = 0;
  const PackedMatrix* w = nullptr;
  const float* bias = nullptr;  // padded to the panels; w->bias() unless overridden
  float slope = 1.0f;  // epilogue max(v, slope * v) after the bias
  float* y = nullptr;  // m x w->rows(), row stride ldy
  std::size_t ldy = 0;
};

// Rows [begin, end) of y = act(x w^T + bias).
using GemmRowsFn = void (*)(const GemmArgs&, std::size_t begin, std::size_t end);
// colmax[o] = max over rows [begin, end) of (x w^T)[i][o]; colmax holds
// panel_count * panel_width floats, already filled by the caller.
using GemmColumnMaxFn = void (*)(const GemmArgs&, std::size_t begin, std::size_t end, float* colmax);

void gemm_rows_sse42(const GemmArgs&, std::size_t, std::size_t);
void gemm_rows_avx2(const GemmArgs&, std::size_t, std::size_t);
void gemm_rows_avx512(const GemmArgs&, std::size_t, std::size_t);
void gemm_column_max_sse42(const GemmArgs&, std::size_t, std::size_t, float*);
void gemm_column_max_avx2(const GemmArgs&, std::size_t, std::size_t, float*);
void gemm_column_max_avx512(const GemmArgs&, std::size_t, std::size_t, float*);

}  // namespace sarmap::kernels::detail
