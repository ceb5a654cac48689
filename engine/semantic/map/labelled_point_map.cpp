#include "engine/semantic/map/labelled_point_map.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/core/error.hpp"
#include "engine/core/metres_text.hpp"
#include "engine/core/prefetched_key_walk.hpp"
#include "engine/semantic/grid_keys.hpp"

namespace sarmap {

LabelledPointMap::LabelledPointMap(double cell, std::size_t classes)
    : cell_(cell), inverse_cell_(1.0 / cell), classes_(classes) {
  if (!(cell >= 0.01) || !std::isfinite(cell)) {
    throw Error(ErrorCode::InvalidArgument,
                "the labelled point map's cell must be at least 0.01 m, got " + std::to_string(cell));
  }
  if (classes == 0 || classes > 255) {
    throw Error(ErrorCode::InvalidArgument, "the labelled point map needs 1 to 255 classes, got " +
                                                std::to_string(classes));
  }
}

std::uint64_t LabelledPointMap::cell_key(double x, double y, double z) const {
  return grid_keys::cell_key(grid_keys::index(x, inverse_cell_), grid_keys::index(y, inverse_cell_),
                             grid_keys::index(z, inverse_cell_));
}

std::vector<std::uint32_t> LabelledPointMap::insert(const PointBuffer& scan, std::vector<std::uint32_t>& added) {
  added.clear();
  std::vector<std::uint32_t> of_point(scan.size(), kNoPoint);
  const bool colours = scan.has_colors() && (points_.empty() || points_.has_colors());
  if (colours && !points_.has_colors()) points_.enable_colors();
  std::uint32_t last_point = kNoPoint;
  const auto reached_cell = [&](std::size_t i, std::uint64_t& key) {
    const double x = scan.x()[i], y = scan.y()[i], z = scan.z()[i];
    if (!in_reach(x, y, z)) return false;
    key = cell_key(x, y, z);
    return true;
  };
  // A repeat falls in the cell of the reached point before it.
  const auto place = [&](std::size_t i, std::uint64_t key, bool repeat) {
    if (!repeat) {
      last_point = index_.find_or_insert(key);
      if (last_point == points_.size()) {  // a new cell
        const std::uint32_t p = last_point;
        points_.push_back(scan.x()[i], scan.y()[i], scan.z()[i]);
        if (points_.has_colors()) {
          points_.red()[p] = colours ? scan.red()[i] : 0;
          points_.green()[p] = colours ? scan.green()[i] : 0;
          points_.blue()[p] = colours ? scan.blue()[i] : 0;
        }
        added.push_back(p);
      }
    }
    of_point[i] = last_point;
  };
  walk_keys_prefetched(index_, 0, scan.size(), reached_cell, place);
  sums_.resize(points_.size() * classes_, 0);
  hits_.resize(points_.size(), 0);
  return of_point;
}

std::size_t LabelledPointMap::merge(const LabelledPointMap& other, const Pose& other_to_this) {
  if (other.cell_ != cell_ || other.classes_ != classes_) {
    throw Error(ErrorCode::InvalidArgument,
                "merge: cannot merge a labelled point map of " + metres_text(other.cell_) + " cells and " +
                    std::to_string(other.classes_) + " classes into one of " + metres_text(cell_) + " cells and " +
                    std::to_string(classes_) + " classes");
  }
  PointBuffer moved = other.points_;
  other_to_this.apply(moved);
  std::vector<std::uint32_t> added;
  const std::vector<std::uint32_t> of_point = insert(moved, added);
  for (std::size_t p = 0; p < of_point.size(); ++p) {
    const std::uint32_t q = of_point[p];
    if (q == kNoPoint) continue;
    for (std::size_t c = 0; c < classes_; ++c) sums_[q * classes_ + c] += other.sums_[p * classes_ + c];
    hits_[q] += other.hits_[p];
  }
  return added.size();
}

std::uint32_t LabelledPointMap::find(double x, double y, double z) const {
  if (!in_reach(x, y, z)) {
    return kNoPoint;
  }
  const std::uint32_t p = index_.find(cell_key(x, y, z));
  return p == FlatKeyIndex::kAbsent ? kNoPoint : p;
}

std::uint32_t LabelledPointMap::nearest_classified(double x, double y, double z) const {
  if (!in_reach(x, y, z)) {
    return kNoPoint;
  }
  const std::int64_t ci = grid_keys::index(x, inverse_cell_), cj = grid_keys::index(y, inverse_cell_),
                     ck = grid_keys::index(z, inverse_cell_);
  std::uint32_t best = kNoPoint;
  double best_d2 = 0.0;
  for (std::int64_t di = -1; di <= 1; ++di) {
    for (std::int64_t dj = -1; dj <= 1; ++dj) {
      for (std::int64_t dk = -1; dk <= 1; ++dk) {
        const std::uint32_t p = index_.find(grid_keys::cell_key(ci + di, cj + dj, ck + dk));
        if (p == FlatKeyIndex::kAbsent || hits_[p] == 0) continue;
        const double ex = points_.x()[p] - x, ey = points_.y()[p] - y, ez = points_.z()[p] - z;
        const double d2 = ex * ex + ey * ey + ez * ez;
        if (best == kNoPoint || d2 < best_d2 || (d2 == best_d2 && p < best)) {
          best = p;
          best_d2 = d2;
        }
      }
    }
  }
  return best;
}

void LabelledPointMap::fuse(std::span<const std::uint32_t> points, std::span<const std::uint8_t> scores, int sign) {
  if (scores.size() != points.size() * classes_) {
    throw Error(ErrorCode::InvalidArgument, "fuse: " + std::to_string(scores.size()) + " scores for " +
                                                std::to_string(points.size()) + " points of " +
                                                std::to_string(classes_) + " classes");
  }
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::uint32_t p = points[k];
    std::uint32_t* sum = sums_.data() + static_cast<std::size_t>(p) * classes_;
    const std::uint8_t* row = scores.data() + k * classes_;
    if (sign > 0) {
      for (std::size_t c = 0; c < classes_; ++c) sum[c] += row[c];
      ++hits_[p];
    } else {
      for (std::size_t c = 0; c < classes_; ++c) sum[c] -= row[c];
      --hits_[p];
    }
  }
}

void LabelledPointMap::mean_scores(std::uint32_t p, float* out) const {
  const std::uint32_t* sum = sums_.data() + static_cast<std::size_t>(p) * classes_;
  const double scale = hits_[p] == 0 ? 0.0 : 1.0 / (static_cast<double>(kScoreScale) * hits_[p]);
  for (std::size_t c = 0; c < classes_; ++c) out[c] = static_cast<float>(sum[c] * scale);
}

int LabelledPointMap::best_channel(std::uint32_t p) const {
  if (hits_[p] == 0) return -1;
  const std::uint32_t* sum = sums_.data() + static_cast<std::size_t>(p) * classes_;
  std::size_t best = 0;
  for (std::size_t c = 1; c < classes_; ++c) {
    if (sum[c] > sum[best]) best = c;
  }
  return static_cast<int>(best);
}

std::vector<std::uint32_t> LabelledPointMap::keep_only(const std::vector<std::uint8_t>& keep) {
  if (keep.size() != points_.size()) {
    throw Error(ErrorCode::InvalidArgument, "keep_only: " + std::to_string(keep.size()) + " flags for " +
                                                std::to_string(points_.size()) + " points");
  }
  std::vector<std::uint32_t> renumbered(points_.size(), kNoPoint);
  std::vector<std::uint32_t> kept;
  for (std::uint32_t p = 0; p < points_.size(); ++p) {
    if (!keep[p]) continue;
    renumbered[p] = static_cast<std::uint32_t>(kept.size());
    kept.push_back(p);
  }
  if (kept.size() == points_.size()) return renumbered;
  std::vector<std::uint32_t> sums(kept.size() * classes_), hits(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) {
    std::copy_n(sums_.data() + static_cast<std::size_t>(kept[k]) * classes_, classes_, sums.data() + k * classes_);
    hits[k] = hits_[kept[k]];
  }
  points_ = points_.select(kept);
  sums_ = std::move(sums);
  hits_ = std::move(hits);
  index_ = FlatKeyIndex(points_.size());
  for (std::uint32_t p = 0; p < points_.size(); ++p) index_.find_or_insert(cell_key(points_.x()[p], points_.y()[p], points_.z()[p]));
  return renumbered;
}

std::size_t LabelledPointMap::memory_bytes() const {
  const std::size_t per_point = 3 * sizeof(float) + (points_.has_colors() ? 3 : 0);
  return points_.size() * per_point + index_.memory_bytes() + sums_.capacity() * sizeof(std::uint32_t) +
         hits_.capacity() * sizeof(std::uint32_t);
}

void LabelledPointMap::save_state(StateWriter& out) const {
  out.tag("LPMP");
  out.put(cell_);
  out.put<std::uint64_t>(classes_);
  points_.save_state(out);
  out.put_vector(sums_);
  out.put_vector(hits_);
}

void LabelledPointMap::load_state(StateReader& in) {
  in.expect_tag("LPMP");
  const double cell = in.get<double>();
  const auto classes = in.get<std::uint64_t>();
  if (cell != cell_ || classes != classes_) {
    in.fail("the labelled point map was saved with cell " + std::to_string(cell) + " m and " +
            std::to_string(classes) + " classes, this run has " + std::to_string(cell_) + " m and " +
            std::to_string(classes_));
  }
  PointBuffer points;
  points.load_state(in);
  std::vector<std::uint32_t> sums = in.get_vector<std::uint32_t>();
  std::vector<std::uint32_t> hits = in.get_vector<std::uint32_t>();
  if (sums.size() != points.size() * classes_ || hits.size() != points.size()) {
    in.fail("the labelled point map's score arrays do not match its " + std::to_string(points.size()) + " points");
  }
  FlatKeyIndex index(points.size());
  for (std::uint32_t p = 0; p < points.size(); ++p) {
    if (index.find_or_insert(cell_key(points.x()[p], points.y()[p], points.z()[p])) != p) {
      in.fail("the labelled point map holds two points in one cell");
    }
  }
  points_ = std::move(points);
  index_ = std::move(index);
  sums_ = std::move(sums);
  hits_ = std::move(hits);
}

}  // namespace sarmap
