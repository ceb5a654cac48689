// DGCNN's EdgeConv after the algebraic split (see edge_conv_body.hpp): the
// fused gather -> add -> LeakyReLU -> 1x1 conv -> max-over-k kernel for a
// two-convolution EdgeConv, and the gather-max for a one-convolution one.
// Parallel over points with oneTBB; results do not depend on threads.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/edge_conv_limits.hpp"
#include "kernels/packed_matrix.hpp"

namespace sarmap::kernels {

// For every point i < count:
//   out[i][o] = act2(max_j sum_h w2[o][h] * act1(a[idx[i][j]][h] + b[i][h]) + bias2[o])
// a, b: count x hidden (row stride ld_ab), idx: count x k, w2: out x hidden
// with its bias; act(v) = max(v, slope * v), 0 <= slope <= 1.
// Requires hidden <= kEdgeMaxHidden, w2.rows() <= kEdgeMaxOut, k <= kEdgeMaxK.
void edge_conv_max(const float* a, const float* b, std::size_t ld_ab, std::size_t count, std::size_t hidden,
                   const std::uint32_t* idx, std::size_t k, float slope1, const PackedMatrix& w2, float slope2,
                   float* out, std::size_t ldo);

// out[i][c] = act(max_j a[idx[i][j]][c] + b[i][c]) for c < channels.
void gather_max(const float* a, const float* b, std::size_t ld_ab, std::size_t count, std::size_t channels,
                const std::uint32_t* idx, std::size_t k, float slope, SimdLevel level, float* out, std::size_t ldo);

// Scalar references of both; w2 row-major (out x hidden), bias2 may be null.
void edge_conv_max_reference(const float* a, const float* b, std::size_t ld_ab, std::size_t count,
                             std::size_t hidden, const std::uint32_t* idx, std::size_t k, float slope1,
                             const float* w2, const float* bias2, std::size_t out_channels, float slope2, float* out,
                             std::size_t ldo);
void gather_max_reference(const float* a, const float* b, std::size_t ld_ab, std::size_t count, std::size_t channels,
                          const std::uint32_t* idx, std::size_t k, float slope, float* out, std::size_t ldo);

}  // namespace sarmap::kernels
