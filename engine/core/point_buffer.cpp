#include "engine/core/point_buffer.hpp"

#include <cmath>
#include <limits>

#include "engine/core/capacity_bytes.hpp"

namespace sarmap {

template <class Self, class Fn>
void PointBuffer::for_each_array(Self& self, Fn&& fn) {
  fn(self.x_);
  fn(self.y_);
  fn(self.z_);
  if (self.has_labels_) fn(self.labels_);
  if (self.has_gt_labels_) fn(self.gt_labels_);
  if (self.has_colors_) {
    fn(self.red_);
    fn(self.green_);
    fn(self.blue_);
  }
  if (self.has_intensity_) fn(self.intensity_);
  if (self.has_normals_) {
    fn(self.nx_);
    fn(self.ny_);
    fn(self.nz_);
  }
  for (auto& s : self.scores_) fn(s);
}

std::size_t PointBuffer::memory_bytes() const {
  // The enabled attributes' arrays: an attribute is never disabled, so the
  // others have never held anything.
  std::size_t bytes = 0;
  for_each_array(*this, [&bytes](const auto& a) { bytes += capacity_bytes(a); });
  return bytes;
}

void PointBuffer::resize(std::size_t count) {
  for_each_array(*this, [count](auto& a) { a.resize(count); });
}

void PointBuffer::reserve(std::size_t count) {
  for_each_array(*this, [count](auto& a) { a.reserve(count); });
}

void PointBuffer::push_back(float x, float y, float z) {
  const std::size_t n = size();
  resize(n + 1);
  x_[n] = x;
  y_[n] = y;
  z_[n] = z;
}

void PointBuffer::enable_labels() {
  if (!has_labels_) labels_.assign(size(), 0);
  has_labels_ = true;
}
void PointBuffer::enable_gt_labels() {
  if (!has_gt_labels_) gt_labels_.assign(size(), 0);
  has_gt_labels_ = true;
}
void PointBuffer::enable_colors() {
  if (!has_colors_) {
    red_.assign(size(), 0);
    green_.assign(size(), 0);
    blue_.assign(size(), 0);
  }
  has_colors_ = true;
}
void PointBuffer::enable_intensity() {
  if (!has_intensity_) intensity_.assign(size(), 0.0f);
  has_intensity_ = true;
}
void PointBuffer::enable_normals() {
  if (!has_normals_) {
    nx_.assign(size(), 0.0f);
    ny_.assign(size(), 0.0f);
    nz_.assign(size(), 0.0f);
  }
  has_normals_ = true;
}

std::size_t PointBuffer::add_score(const std::string& name) {
  const std::size_t existing = find_score(name);
  if (existing < score_count()) return existing;
  score_names_.push_back(name);
  scores_.emplace_back(size(), 0.0f);
  return score_names_.size() - 1;
}

std::size_t PointBuffer::find_score(const std::string& name) const {
  for (std::size_t i = 0; i < score_names_.size(); ++i) {
    if (score_names_[i] == name) return i;
  }
  return score_names_.size();
}

void PointBuffer::enable_attributes_of(const PointBuffer& other) {
  if (other.has_labels_) enable_labels();
  if (other.has_gt_labels_) enable_gt_labels();
  if (other.has_colors_) enable_colors();
  if (other.has_intensity_) enable_intensity();
  if (other.has_normals_) enable_normals();
  for (const auto& name : other.score_names_) add_score(name);
}

namespace {
template <class V>
void append_array(V& dst, const V& src, bool src_has, std::size_t src_count) {
  if (src_has) {
    dst.insert(dst.end(), src.begin(), src.end());
  } else {
    dst.resize(dst.size() + src_count);
  }
}
}  // namespace

void PointBuffer::append(const PointBuffer& other) {
  enable_attributes_of(other);
  const std::size_t n = other.size();
  append_array(x_, other.x_, true, n);
  append_array(y_, other.y_, true, n);
  append_array(z_, other.z_, true, n);
  if (has_labels_) append_array(labels_, other.labels_, other.has_labels_, n);
  if (has_gt_labels_) append_array(gt_labels_, other.gt_labels_, other.has_gt_labels_, n);
  if (has_colors_) {
    append_array(red_, other.red_, other.has_colors_, n);
    append_array(green_, other.green_, other.has_colors_, n);
    append_array(blue_, other.blue_, other.has_colors_, n);
  }
  if (has_intensity_) append_array(intensity_, other.intensity_, other.has_intensity_, n);
  if (has_normals_) {
    append_array(nx_, other.nx_, other.has_normals_, n);
    append_array(ny_, other.ny_, other.has_normals_, n);
    append_array(nz_, other.nz_, other.has_normals_, n);
  }
  for (std::size_t c = 0; c < score_names_.size(); ++c) {
    const std::size_t src = other.find_score(score_names_[c]);
    if (src < other.score_count()) {
      append_array(scores_[c], other.scores_[src], true, n);
    } else {
      scores_[c].resize(scores_[c].size() + n);
    }
  }
}

PointBuffer PointBuffer::select(std::span<const std::uint32_t> indices) const {
  PointBuffer out;
  out.enable_attributes_of(*this);
  out.resize(indices.size());
  auto copy = [&indices](const auto& src, auto& dst) {
    for (std::size_t i = 0; i < indices.size(); ++i) dst[i] = src[indices[i]];
  };
  copy(x_, out.x_);
  copy(y_, out.y_);
  copy(z_, out.z_);
  if (has_labels_) copy(labels_, out.labels_);
  if (has_gt_labels_) copy(gt_labels_, out.gt_labels_);
  if (has_colors_) {
    copy(red_, out.red_);
    copy(green_, out.green_);
    copy(blue_, out.blue_);
  }
  if (has_intensity_) copy(intensity_, out.intensity_);
  if (has_normals_) {
    copy(nx_, out.nx_);
    copy(ny_, out.ny_);
    copy(nz_, out.nz_);
  }
  for (std::size_t c = 0; c < scores_.size(); ++c) copy(scores_[c], out.scores_[c]);
  return out;
}

template <class Keeps>
std::size_t PointBuffer::keep_where(Keeps keeps) {
  const std::size_t n = size();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) kept += keeps(i) ? 1 : 0;  // no stores: the compiler vectorises it
  if (kept == n) return 0;
  std::vector<std::uint8_t> keep(n);
  for (std::size_t i = 0; i < n; ++i) keep[i] = keeps(i);
  for_each_array(*this, [&keep, n](auto& a) {
    std::size_t out = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (keep[i]) a[out++] = a[i];
    }
    a.resize(out);
  });
  return n - kept;
}

namespace {

// std::isfinite in a form the compiler vectorises: false for NaN and +-inf.
inline bool finite(float v) { return std::fabs(v) <= std::numeric_limits<float>::max(); }
// All three finite: summed rather than chained with &&, which would branch
// per axis and keep the loop from vectorising.
inline bool finite(float x, float y, float z) { return finite(x) + finite(y) + finite(z) == 3; }

}  // namespace

std::size_t PointBuffer::remove_non_finite() {
  return keep_where([this](std::size_t i) { return finite(x_[i], y_[i], z_[i]); });
}

std::size_t PointBuffer::remove_farther_than(const Eigen::Vector3d& centre, double distance) {
  const double squared = distance * distance;
  const double cx = centre.x(), cy = centre.y(), cz = centre.z();
  return keep_where([&](std::size_t i) {
    const double dx = x_[i] - cx, dy = y_[i] - cy, dz = z_[i] - cz;
    return dx * dx + dy * dy + dz * dz <= squared;  // false for NaN
  });
}

Bounds PointBuffer::bounds() const {
  Bounds b;
  for (std::size_t i = 0; i < size(); ++i) b.extend(Eigen::Vector3d(x_[i], y_[i], z_[i]));
  return b;
}

}  // namespace sarmap
