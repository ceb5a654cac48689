// The accumulated map the network classifies: the scans' points thinned to
// one point per cell of a 3-D grid (the first point seen in the cell stays),
// each with its per-class scores fused over the DGCNN blocks that classified
// it. Scores are kept as integer sums of softmax probabilities quantised to
// 1/255, so a block's old contribution can be taken out exactly when the
// block is classified again, in any order, with the same result.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/flat_key_index.hpp"
#include "engine/core/point_buffer.hpp"
#include "engine/core/pose.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/semantic/grid_keys.hpp"

namespace sarmap {

// A map point's quantised probability of one class: round(p * kScoreScale).
inline constexpr std::uint32_t kScoreScale = 255;

class LabelledPointMap {
 public:
  static constexpr std::uint32_t kNoPoint = 0xffffffffu;

  // One kept point per `cell` metres (>= 1 cm) and `classes` score channels.
  // Throws sarmap::Error (InvalidArgument) otherwise.
  LabelledPointMap(double cell, std::size_t classes);

  double cell() const { return cell_; }
  std::size_t classes() const { return classes_; }
  std::size_t size() const { return points_.size(); }
  // Positions (and colours when the scans had them) of the kept points.
  const PointBuffer& points() const { return points_; }

  // For each scan point, the index of the map point of its cell; cells not
  // held yet take the scan point as their map point. Points beyond 10 km
  // (which the metric map rejects) or not finite get kNoPoint.
  // `added` receives the indices of the map points this call created.
  std::vector<std::uint32_t> insert(const PointBuffer& scan, std::vector<std::uint32_t>& added);
  // The map point of the cell holding (x, y, z), or kNoPoint.
  std::uint32_t find(double x, double y, double z) const;
  // The classified map point nearest to (x, y, z) among the 3 x 3 x 3 cells
  // around its cell (the lowest index on ties), or kNoPoint.
  std::uint32_t nearest_classified(double x, double y, double z) const;

  // The point whose scores stand for p's: p once a block has classified it,
  // else its nearest classified neighbour (nearest_classified), else kNoPoint.
  std::uint32_t scored_point(std::uint32_t p) const {
    return hits_[p] > 0 ? p : nearest_classified(points_.x()[p], points_.y()[p], points_.z()[p]);
  }
  // Calls fn(p) once for every map point p in voxel `voxel` of a grid of
  // inverse cell size inv_resolution (floor(coordinate * inv_resolution) ==
  // voxel on each axis), as the metric map keys its voxels. Where the voxel
  // is a power of two of this map's cells across (the defaults: 0.05 m
  // voxels of 0.025 m cells), only the cells inside it are looked up:
  // scaling by a power of two is exact, so those cells' points are the
  // voxel's. Otherwise every cell overlapping it is, and each point checked.
  template <class Fn>
  void for_each_in_voxel(const std::int64_t voxel[3], double inv_resolution, Fn&& fn) const;

  // Adds (sign +1) or takes out (sign -1) one block's quantised scores of
  // `points` (points.size() x classes, row-major).
  void fuse(std::span<const std::uint32_t> points, std::span<const std::uint8_t> scores, int sign);

  // How many block classifications point p's scores hold (0: unclassified).
  std::uint32_t hits(std::uint32_t p) const { return hits_[p]; }
  // Mean probabilities of point p over its blocks into out[0 .. classes);
  // zeros when hits(p) == 0.
  void mean_scores(std::uint32_t p, float* out) const;
  // Point p's integer score sums (classes() of them: kScoreScale x the sum
  // of its blocks' probabilities), exact for arg-max without rounding.
  std::span<const std::uint32_t> score_sums(std::uint32_t p) const {
    return std::span(sums_).subspan(static_cast<std::size_t>(p) * classes_, classes_);
  }
  // The channel with the highest mean score (the first on ties), or -1 when
  // unclassified.
  int best_channel(std::uint32_t p) const;

  // Takes `other`'s points, carried into this map's frame by `other_to_this`:
  // a cell this map lacks takes the other's point with its scores; a cell
  // both hold keeps this map's point and adds the other's score sums and
  // block counts to it (its mean is then over both maps' blocks). Returns
  // how many points were added. Throws sarmap::Error (InvalidArgument)
  // naming both for another cell size or class count, before any change.
  std::size_t merge(const LabelledPointMap& other, const Pose& other_to_this);

  // Keeps only the points whose keep[p] is non-zero, in order, with their
  // cells and scores; returns for every old index its new one or kNoPoint.
  std::vector<std::uint32_t> keep_only(const std::vector<std::uint8_t>& keep);

  // Bytes held: points, cell index and score sums.
  std::size_t memory_bytes() const;

  void save_state(StateWriter& out) const;
  // Throws sarmap::Error (Parse) for another cell size or class count, or
  // arrays that disagree in length.
  void load_state(StateReader& in);

 private:
  // The metric map's limits: farther points are never mapped.
  static constexpr double kMaxCoordinate = 1.0e4;
  static bool in_reach(double x, double y, double z) {
    return std::abs(x) <= kMaxCoordinate && std::abs(y) <= kMaxCoordinate && std::abs(z) <= kMaxCoordinate;
  }
  std::uint64_t cell_key(double x, double y, double z) const;

  double cell_;
  double inverse_cell_;
  std::size_t classes_;
  PointBuffer points_;
  // Cell key -> point: a cell's point is the index the table gives it, as
  // both count up from 0 in arrival order. Open addressing, because every
  // scan point looks its cell up and every unclassified one 27 cells.
  FlatKeyIndex index_;
  std::vector<std::uint32_t> sums_;                          // size() x classes
  std::vector<std::uint32_t> hits_;
};

template <class Fn>
void LabelledPointMap::for_each_in_voxel(const std::int64_t voxel[3], double inv_resolution, Fn&& fn) const {
  std::int64_t first[3], last[3];
  int exponent = 0;
  const double mantissa = std::frexp(inverse_cell_ / inv_resolution, &exponent);
  const double across = std::ldexp(1.0, exponent - 1);
  const bool exact = mantissa == 0.5 && exponent >= 1 && inverse_cell_ == across * inv_resolution;
  for (int a = 0; a < 3; ++a) {
    const double lo = static_cast<double>(voxel[a]) / inv_resolution;
    if (!(std::abs(lo) <= kMaxCoordinate)) return;
    if (exact) {
      first[a] = voxel[a] * static_cast<std::int64_t>(across);
      last[a] = first[a] + static_cast<std::int64_t>(across) - 1;
    } else {
      // A cell beyond each edge too: the divisions that give the voxel's edges may round past a
      // point of the voxel, down as well as up.
      first[a] = static_cast<std::int64_t>(std::floor(lo * inverse_cell_)) - 1;
      const double hi = static_cast<double>(voxel[a] + 1) / inv_resolution;
      last[a] = static_cast<std::int64_t>(std::floor(hi * inverse_cell_)) + 1;
    }
  }
  const auto in_voxel = [&](std::uint32_t p) {
    const float* xyz[3] = {points_.x().data(), points_.y().data(), points_.z().data()};
    for (int a = 0; a < 3; ++a) {
      if (static_cast<std::int64_t>(std::floor(static_cast<double>(xyz[a][p]) * inv_resolution)) != voxel[a]) return false;
    }
    return true;
  };
  for (std::int64_t i = first[0]; i <= last[0]; ++i) {
    for (std::int64_t j = first[1]; j <= last[1]; ++j) {
      for (std::int64_t k = first[2]; k <= last[2]; ++k) {
        const std::uint32_t p = index_.find(grid_keys::cell_key(i, j, k));
        if (p != FlatKeyIndex::kAbsent && (exact || in_voxel(p))) fn(p);
      }
    }
  }
}

}  // namespace sarmap
