// Carries per-sample DGCNN scores back to every point of the scan: a sampled
// point keeps its own, an unsampled one takes its nearest sample's (3-D) in the
// same block, and points in several (overlapping) blocks average them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/point_buffer.hpp"
#include "engine/semantic/dgcnn/block_partition.hpp"

namespace sarmap {

class ScoreAccumulator {
 public:
  ScoreAccumulator(std::size_t point_count, std::size_t classes);

  // `samples` are positions into block.points; `scores` is samples.size() x
  // classes, row-major. Not thread-safe: call once per block in any order
  // (sums are exact to rounding in block order; callers keep the order fixed).
  void add_block(const PointBuffer& points, const Block& block, std::span<const std::uint32_t> samples,
                 std::span<const float> scores);

  std::size_t classes() const { return classes_; }
  // How many blocks scored point p (0: only in dropped blocks).
  std::uint32_t hits(std::size_t p) const { return hits_[p]; }
  // Mean score of point p over its blocks (zeros when hits(p) == 0).
  std::vector<float> mean(std::size_t p) const;
  // The same into out[0 .. classes), without allocating.
  void mean(std::size_t p, float* out) const;

 private:
  std::size_t classes_;
  std::vector<double> sums_;  // point_count x classes
  std::vector<std::uint32_t> hits_;
};

// For each of block.points, the index into `samples` of its own copy or of
// the nearest (3-D) sampled point (the lowest sample index among equally
// near ones). Uses a 3-D grid; nearest_sample_reference
// is the brute-force definition it is tested against.
std::vector<std::uint32_t> nearest_sample(const PointBuffer& points, const Block& block,
                                          std::span<const std::uint32_t> samples);
std::vector<std::uint32_t> nearest_sample_reference(const PointBuffer& points, const Block& block,
                                                    std::span<const std::uint32_t> samples);

}  // namespace sarmap
