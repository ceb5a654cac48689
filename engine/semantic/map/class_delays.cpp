#include "engine/semantic/map/class_delays.hpp"

#include <algorithm>
#include <numeric>

#include "engine/semantic/map/labelled_point_map.hpp"

namespace sarmap {

void ClassDelays::added(std::span<const std::uint32_t> added, std::uint32_t scan) {
  for (const std::uint32_t p : added) waiting_.push_back({p, scan});
}

void ClassDelays::record(std::uint32_t delay) {
  const std::uint32_t bin = std::min(delay, kMaxDelay);
  if (histogram_.size() <= bin) histogram_.resize(bin + 1, 0);
  ++histogram_[bin];
}

void ClassDelays::renumber(const std::vector<std::uint32_t>& renumbered) {
  std::size_t kept = 0;
  for (const Waiting& w : waiting_) {
    const std::uint32_t now = w.point < renumbered.size() ? renumbered[w.point] : LabelledPointMap::kNoPoint;
    if (now != LabelledPointMap::kNoPoint) waiting_[kept++] = {now, w.scan};
  }
  waiting_.resize(kept);
}

void ClassDelays::merge(const ClassDelays& other) {
  if (histogram_.size() < other.histogram_.size()) histogram_.resize(other.histogram_.size(), 0);
  for (std::size_t d = 0; d < other.histogram_.size(); ++d) histogram_[d] += other.histogram_[d];
}

std::vector<std::uint32_t> ClassDelays::waiting_added_by(std::uint32_t scan) const {
  const auto first = std::lower_bound(waiting_.begin(), waiting_.end(), scan,
                                      [](const Waiting& w, std::uint32_t s) { return w.scan < s; });
  std::vector<std::uint32_t> points;
  for (auto it = first; it != waiting_.end() && it->scan == scan; ++it) points.push_back(it->point);
  return points;
}

bool ClassDelays::consistent_with(std::size_t points, std::uint32_t scans) const {
  return std::all_of(waiting_.begin(), waiting_.end(),
                     [&](const Waiting& w) { return w.point < points && w.scan <= scans; });
}

std::uint64_t ClassDelays::recorded() const {
  return std::accumulate(histogram_.begin(), histogram_.end(), std::uint64_t{0});
}

std::uint32_t ClassDelays::quantile(double fraction) const {
  const std::uint64_t total = recorded();
  if (total == 0) return 0;
  // The first bin at which the running count reaches fraction x total.
  const double target = std::clamp(fraction, 0.0, 1.0) * static_cast<double>(total);
  std::uint64_t running = 0;
  for (std::size_t d = 0; d < histogram_.size(); ++d) {
    running += histogram_[d];
    if (running > 0 && static_cast<double>(running) >= target) return static_cast<std::uint32_t>(d);
  }
  return static_cast<std::uint32_t>(histogram_.size() - 1);
}

void ClassDelays::save_state(StateWriter& out) const {
  out.tag("CDLY");
  out.put_vector(waiting_);
  out.put_vector(histogram_);
}

void ClassDelays::load_state(StateReader& in) {
  in.expect_tag("CDLY");
  auto waiting = in.get_vector<Waiting>();
  auto histogram = in.get_vector<std::uint64_t>();
  if (histogram.size() > kMaxDelay + 1) in.fail("the class delays' histogram is longer than its last bin");
  if (!std::is_sorted(waiting.begin(), waiting.end(),
                      [](const Waiting& a, const Waiting& b) { return a.scan < b.scan; })) {
    in.fail("the class delays' waiting points are out of order");
  }
  waiting_ = std::move(waiting);
  histogram_ = std::move(histogram);
}

}  // namespace sarmap
