// The DGCNN semantic-segmentation network ready to run on the CPU: weights
// loaded from safetensors, BatchNorm folded into the convolutions, the first
// convolution of each EdgeConv split into per-point terms, the head's global
// share turned into a per-block bias, and everything packed for the kernels'
// instruction set. forward() maps one (N, C) block to (N, classes) logits.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "engine/semantic/dgcnn/dgcnn_metadata.hpp"
#include "engine/semantic/dgcnn/dgcnn_weights.hpp"
#include "engine/semantic/dgcnn/dgcnn_workspace.hpp"
#include "kernels/packed_matrix.hpp"
#include "kernels/simd_level.hpp"

namespace sarmap {

class DgcnnModel {
 public:
  // Reads a .safetensors model (errors name the file and tensor) and packs it
  // for the kernels' active instruction set.
  static DgcnnModel load(const std::filesystem::path& path);
  static DgcnnModel load(const std::filesystem::path& path, kernels::SimdLevel level);
  DgcnnModel(const DgcnnWeights& weights, DgcnnMetadata metadata, kernels::SimdLevel level);

  std::size_t channels() const { return channels_; }
  std::size_t classes() const { return classes_; }
  std::size_t emb() const { return emb_; }
  std::size_t k() const { return metadata_.k; }
  const DgcnnMetadata& metadata() const { return metadata_; }
  kernels::SimdLevel level() const { return level_; }

  static constexpr std::size_t kMaxBlockPoints = kMaxPointsPerBlock;

  // logits (n x classes(), row-major) of a block of n points with channels()
  // floats each, row-major. Throws sarmap::Error for n == 0, n >
  // kMaxBlockPoints or a non-finite value. Threads: whatever oneTBB arena the caller runs in; the result does
  // not depend on it. `times`, when given, receives per-stage wall time.
  // Rows that repeat others (a sparse block filled up by drawing points
  // again) are computed once, through forward_with_copies().
  void forward(const float* block, std::size_t n, float* logits, DgcnnWorkspace& workspace,
               DgcnnStageTimes* times = nullptr) const;

  // logits of n rows of which row i stands for copies[i] >= 1 identical
  // points: those of forward() on the block with every row repeated that
  // many times (repeated_rows.hpp says when a tie makes them differ), in the
  // time of n rows. Throws as forward() does, and for a zero copy count.
  void forward_with_copies(const float* rows, std::size_t n, const std::uint32_t* copies, float* logits,
                           DgcnnWorkspace& workspace, DgcnnStageTimes* times = nullptr) const;

  // Floating-point operations of forward() on n points (multiply and add
  // counted apart), after the algebraic rewrites.
  double flops(std::size_t n) const;

 private:
  void check_block(const float* block, std::size_t n) const;
  void run(const float* block, std::size_t n, const std::uint32_t* copies, float* logits, DgcnnWorkspace& workspace,
           DgcnnStageTimes* times) const;

  struct EdgeLayer {
    kernels::PackedMatrix split;   // 2E x in: [W1; W2 - W1] with [0; bias]
    kernels::PackedMatrix second;  // E' x E (two-convolution layers only)
    std::size_t hidden = 0, out = 0, in = 0;
  };

  DgcnnMetadata metadata_;
  kernels::SimdLevel level_;
  std::size_t channels_ = 0, classes_ = 0, emb_ = 0, local_ = 0, head1_ = 0, head2_ = 0;
  EdgeLayer edge_[3];
  kernels::PackedMatrix global_;  // conv6, folded
  std::vector<float> head_global_;  // conv7's columns for the global feature: head1 x emb
  std::vector<float> head_bias_;    // conv7's folded bias
  kernels::PackedMatrix head_local_;  // conv7's columns for [x1, x2, x3]
  kernels::PackedMatrix head2_w_;     // conv8
  kernels::PackedMatrix classifier_;  // conv9
};

}  // namespace sarmap
