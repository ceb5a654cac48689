// Pointwise (1x1) convolutions as GEMMs over point-major feature rows, with
// the bias and LeakyReLU fused into the store; parallel over row chunks with
// oneTBB, each output row computed by the same code whatever the thread count.
#pragma once

#include <cstddef>

#include "kernels/packed_matrix.hpp"

namespace sarmap::kernels {

// y[i][o] = act(sum_c x[i][c] * w[o][c] + bias[o]) for i < m, o < w.rows(),
// with act(v) = max(v, slope * v): slope 1 is the identity, 0.2 LeakyReLU(0.2)
// (0 <= slope <= 1). x rows have stride ldx (>= w.cols()), y rows ldy.
// The instruction set is w.level() (it must be supported by this CPU).
void gemm_bias_act(const float* x, std::size_t ldx, std::size_t m, const PackedMatrix& w, float slope, float* y,
                   std::size_t ldy);
// The same with a bias computed at run time instead of w's (the DGCNN head,
// whose global-feature share is a per-block bias): bias holds
// w.panel_count() * w.panel_width() floats, 64-byte aligned.
void gemm_bias_act(const float* x, std::size_t ldx, std::size_t m, const PackedMatrix& w, const float* bias,
                   float slope, float* y, std::size_t ldy);

// colmax[o] = max over i < m of sum_c x[i][c] * w[o][c] (no bias: a caller
// with a monotone activation applies bias and activation once afterwards).
// colmax holds w.rows() floats. m >= 1.
void gemm_column_max(const float* x, std::size_t ldx, std::size_t m, const PackedMatrix& w, float* colmax);

// Plain scalar references (weights row-major rows x cols, bias may be null).
void gemm_bias_act_reference(const float* x, std::size_t ldx, std::size_t m, const float* w, const float* bias,
                             std::size_t rows, std::size_t cols, float slope, float* y, std::size_t ldy);
void gemm_column_max_reference(const float* x, std::size_t ldx, std::size_t m, const float* w, std::size_t rows,
                               std::size_t cols, float* colmax);

}  // namespace sarmap::kernels
