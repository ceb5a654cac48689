// Nearest-sample search on a 3-D grid of the block's samples, searched in
// growing shells until no unvisited cell can hold anything nearer.
#include "engine/semantic/dgcnn/score_carry_back.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/core/error.hpp"

namespace sarmap {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

double dist2(const PointBuffer& pts, std::uint32_t a, std::uint32_t b) {
  const double dx = static_cast<double>(pts.x()[a]) - pts.x()[b];
  const double dy = static_cast<double>(pts.y()[a]) - pts.y()[b];
  const double dz = static_cast<double>(pts.z()[a]) - pts.z()[b];
  return dx * dx + dy * dy + dz * dz;
}

// Own copy when sampled (first copy), kNone otherwise.
std::vector<std::uint32_t> own_copies(const Block& block, std::span<const std::uint32_t> samples) {
  std::vector<std::uint32_t> own(block.points.size(), kNone);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    if (samples[s] >= block.points.size()) {
      throw Error(ErrorCode::InvalidArgument, "score carry-back: sample position " + std::to_string(samples[s]) +
                                                  " past the block's " + std::to_string(block.points.size()) + " points");
    }
    if (own[samples[s]] == kNone) own[samples[s]] = static_cast<std::uint32_t>(s);
  }
  return own;
}

}  // namespace

std::vector<std::uint32_t> nearest_sample_reference(const PointBuffer& points, const Block& block,
                                                    std::span<const std::uint32_t> samples) {
  std::vector<std::uint32_t> out = own_copies(block, samples);
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (out[i] != kNone) continue;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s < samples.size(); ++s) {
      const double d = dist2(points, block.points[i], block.points[samples[s]]);
      if (d < best) best = d, out[i] = static_cast<std::uint32_t>(s);
    }
  }
  return out;
}

std::vector<std::uint32_t> nearest_sample(const PointBuffer& points, const Block& block,
                                          std::span<const std::uint32_t> samples) {
  std::vector<std::uint32_t> out = own_copies(block, samples);
  // Cubic cells: 32 across the block in x and y, as many as the samples'
  // height needs in z (at most kMaxLayers; what lies beyond is clamped into
  // the end layers, which only makes those cells hold more). A 2-D grid of
  // columns put a whole wall's height of samples into every point's search.
  constexpr long long kSide = 32, kMaxLayers = 96;
  const double cell = block.size / kSide;
  float z_lo = std::numeric_limits<float>::infinity(), z_hi = -z_lo;
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const float z = points.z()[block.points[samples[s]]];
    z_lo = std::min(z_lo, z), z_hi = std::max(z_hi, z);
  }
  const long long layers =
      samples.empty() ? 1 : std::clamp(static_cast<long long>((z_hi - z_lo) / cell) + 1, 1LL, kMaxLayers);
  auto cell_of = [&](double v, double origin, long long count) {
    return std::clamp(static_cast<long long>(std::floor((v - origin) / cell)), 0LL, count - 1);
  };
  auto cell_index = [&](long long x, long long y, long long z) {
    return static_cast<std::size_t>((z * kSide + y) * kSide + x);
  };
  // Counting sort of samples into cells (the first copy of each sampled point is enough).
  std::vector<std::uint32_t> start(static_cast<std::size_t>(kSide * kSide * layers) + 1, 0), items;
  std::vector<std::uint32_t> sample_cell(samples.size(), kNone);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    if (out[samples[s]] != s) continue;
    const std::uint32_t p = block.points[samples[s]];
    sample_cell[s] = static_cast<std::uint32_t>(cell_index(cell_of(points.x()[p], block.origin_x, kSide),
                                                           cell_of(points.y()[p], block.origin_y, kSide),
                                                           cell_of(points.z()[p], z_lo, layers)));
    ++start[sample_cell[s] + 1];
  }
  for (std::size_t c = 0; c < start.size() - 1; ++c) start[c + 1] += start[c];
  items.resize(start.back());
  // The samples' positions beside them in cell order: the search reads
  // these contiguously instead of through three index arrays.
  std::vector<float> item_x(items.size()), item_y(items.size()), item_z(items.size());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    if (sample_cell[s] == kNone) continue;
    const std::uint32_t k = fill[sample_cell[s]]++;
    const std::uint32_t p = block.points[samples[s]];
    items[k] = static_cast<std::uint32_t>(s);
    item_x[k] = points.x()[p], item_y[k] = points.y()[p], item_z[k] = points.z()[p];
  }
  const long long rings = std::max(kSide, layers);
  // Each point's search is independent and writes only its own entry, so
  // the points are split over threads (serial, it showed in a whole run's time).
  const auto search = [&](std::size_t i) {
    const std::uint32_t p = block.points[i];
    const double px = points.x()[p], py = points.y()[p], pz = points.z()[p];
    const long long cx = cell_of(px, block.origin_x, kSide);
    const long long cy = cell_of(py, block.origin_y, kSide);
    const long long cz = cell_of(pz, z_lo, layers);
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t best_s = kNone;
    const auto visit = [&](long long x, long long y, long long z) {
      const std::size_t c = cell_index(x, y, z);
      for (std::uint32_t k = start[c]; k < start[c + 1]; ++k) {
        // As dist2(): float coordinates differenced in double.
        const double dx = px - item_x[k], dy = py - item_y[k], dz = pz - item_z[k];
        const double d = dx * dx + dy * dy + dz * dz;
        const std::uint32_t s = items[k];
        if (d < best || (d == best && s < best_s)) best = d, best_s = s;
      }
    };
    for (long long r = 0; r < rings; ++r) {
      // Every cell on the shell of ring r is at least (r - 1) cells away in
      // x, y or z (also for points clamped into the grid's end cells).
      if (r >= 1) {
        const double reach = (static_cast<double>(r) - 1.0) * cell;
        if (reach > 0.0 && reach * reach > best) break;
      }
      for (long long z = std::max(cz - r, 0LL); z <= std::min(cz + r, layers - 1); ++z) {
        for (long long y = std::max(cy - r, 0LL); y <= std::min(cy + r, kSide - 1); ++y) {
          if (r == 0 || z == cz - r || z == cz + r || y == cy - r || y == cy + r) {
            for (long long x = std::max(cx - r, 0LL); x <= std::min(cx + r, kSide - 1); ++x) visit(x, y, z);
          } else {  // inside the shell's faces: only its two x ends
            if (cx - r >= 0) visit(cx - r, y, z);
            if (cx + r < kSide) visit(cx + r, y, z);
          }
        }
      }
    }
    out[i] = best_s;
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.size(), 512), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      if (out[i] == kNone) search(i);
    }
  });
  return out;
}

ScoreAccumulator::ScoreAccumulator(std::size_t point_count, std::size_t classes)
    : classes_(classes), sums_(point_count * classes, 0.0), hits_(point_count, 0) {}

void ScoreAccumulator::add_block(const PointBuffer& points, const Block& block, std::span<const std::uint32_t> samples,
                                 std::span<const float> scores) {
  if (scores.size() != samples.size() * classes_) {
    throw Error(ErrorCode::InvalidArgument, "score carry-back: " + std::to_string(scores.size()) + " scores for " +
                                                std::to_string(samples.size()) + " samples of " + std::to_string(classes_) + " classes");
  }
  const std::vector<std::uint32_t> nearest = nearest_sample(points, block, samples);
  for (std::size_t i = 0; i < nearest.size(); ++i) {
    const std::uint32_t p = block.points[i];
    const float* row = scores.data() + static_cast<std::size_t>(nearest[i]) * classes_;
    for (std::size_t c = 0; c < classes_; ++c) sums_[p * classes_ + c] += row[c];
    ++hits_[p];
  }
}

std::vector<float> ScoreAccumulator::mean(std::size_t p) const {
  std::vector<float> out(classes_);
  mean(p, out.data());
  return out;
}

void ScoreAccumulator::mean(std::size_t p, float* out) const {
  for (std::size_t c = 0; c < classes_; ++c) {
    out[c] = hits_[p] == 0 ? 0.0f : static_cast<float>(sums_[p * classes_ + c] / hits_[p]);
  }
}

}  // namespace sarmap
