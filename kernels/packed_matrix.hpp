// The weights and bias of a 1x1 convolution (out x in, row-major as in
// PyTorch) repacked for the GEMM micro-kernel: output channels in panels of
// panel_width(level) columns, each panel stored input-channel-major, zero
// padded, so the kernel streams one panel with aligned vector loads.
#pragma once

#include <cstddef>

#include "kernels/aligned_buffer.hpp"
#include "kernels/simd_level.hpp"

namespace sarmap::kernels {

class PackedMatrix {
 public:
  PackedMatrix() = default;
  // weights: rows x cols (out x in); bias: rows values or nullptr for zeros.
  PackedMatrix(const float* weights, const float* bias, std::size_t rows, std::size_t cols, SimdLevel level);

  std::size_t rows() const { return rows_; }  // output channels
  std::size_t cols() const { return cols_; }  // input channels
  SimdLevel level() const { return level_; }
  std::size_t panel_width() const { return nr_; }
  std::size_t panel_count() const { return (rows_ + nr_ - 1) / nr_; }
  // Panel p: cols() x panel_width() floats; element [c][r] is weight (p*nr + r, c).
  const float* panel(std::size_t p) const { return data_.data() + p * nr_ * cols_; }
  // Bias padded with zeros to panel_count() * panel_width().
  const float* bias() const { return bias_.data(); }

 private:
  std::size_t rows_ = 0, cols_ = 0, nr_ = 8;
  SimdLevel level_ = SimdLevel::Sse42;
  AlignedBuffer<float> data_;
  AlignedBuffer<float> bias_;
};

// Packs `count` points of `dim` floats (row stride `stride`) the same way,
// with each point a "row", after subtracting their mean (written to centre:
// distances do not change, and |b|^2 - 2a.b loses less to rounding), and
// writes their squared norms padded with +inf: the kNN kernel's column side.
// Buffers grow as needed.
void pack_points(const float* points, std::size_t stride, std::size_t count, std::size_t dim, SimdLevel level,
                 AlignedBuffer<float>& panels, AlignedBuffer<float>& norms, AlignedBuffer<float>& centre);

}  // namespace sarmap::kernels
