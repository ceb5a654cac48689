// How many scans pass before a surface gets its class, when classes come
// from the accumulated map: each map point waits from the scan that added it
// until the first classification after which it has a class (its own
// block's scores, or a classified neighbour's it borrows), and that wait, in
// scans, goes into a histogram. Points still waiting are listed, so that the
// figure counts the ones that never got a class too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/state_stream.hpp"

namespace sarmap {

class ClassDelays {
 public:
  // Waits of this many scans or more share the histogram's last bin.
  static constexpr std::uint32_t kMaxDelay = 1000;

  // Map points `added` by scan number `scan` start waiting.
  void added(std::span<const std::uint32_t> added, std::uint32_t scan);
  // After a classification during scan `scan`: every waiting point p with
  // has_class(p) stops waiting, its wait recorded. `from` skips the points
  // that waited longest: after a scan that classified no block only those it
  // added can have a class (a neighbour's).
  template <class HasClass>
  void settle(std::uint32_t scan, HasClass&& has_class, std::size_t from = 0);
  // Follows LabelledPointMap::keep_only (old index -> new index or
  // kNoPoint): a forgotten point stops waiting, unrecorded.
  void renumber(const std::vector<std::uint32_t>& renumbered);
  // Adds another map's recorded waits (a merged map's points are not followed further).
  void merge(const ClassDelays& other);
  // The points added by scan number `scan` that are still waiting, in the
  // order they were added.
  std::vector<std::uint32_t> waiting_added_by(std::uint32_t scan) const;

  // histogram()[d]: points that got their class d scans after they were
  // added (the last bin: kMaxDelay or more).
  const std::vector<std::uint64_t>& histogram() const { return histogram_; }
  std::uint64_t recorded() const;
  std::size_t waiting() const { return waiting_.size(); }
  // False when a waiting point is not one of `points` map points or was
  // added after scan `scans` (a state that does not belong to its map).
  bool consistent_with(std::size_t points, std::uint32_t scans) const;
  // The smallest wait that `fraction` of the recorded points did not
  // exceed (0 when none was recorded).
  std::uint32_t quantile(double fraction) const;

  void save_state(StateWriter& out) const;
  void load_state(StateReader& in);

 private:
  void record(std::uint32_t delay);

  struct Waiting {
    std::uint32_t point;
    std::uint32_t scan;
  };
  std::vector<Waiting> waiting_;  // in the order points were added, so by scan
  std::vector<std::uint64_t> histogram_;
};

template <class HasClass>
void ClassDelays::settle(std::uint32_t scan, HasClass&& has_class, std::size_t from) {
  std::size_t kept = from;
  for (std::size_t i = from; i < waiting_.size(); ++i) {
    const Waiting w = waiting_[i];
    if (has_class(w.point)) {
      record(scan - w.scan);
    } else {
      waiting_[kept++] = w;
    }
  }
  waiting_.resize(kept);
}

}  // namespace sarmap
