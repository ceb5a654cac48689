// Walks a range of points in order, each with its packed key, having
// prefetched the table slots of a batch of keys first: the loops that look
// up or insert a scan's points in a table that outgrows the caches (the
// labelled point map's cells, the Mapper's kept voxels, the segment map's
// voxels). A batch's cache misses then overlap instead of waiting one after
// another. It also owns the shortcut those loops share: neighbouring points
// (a depth image's row, a LiDAR ring) mostly fall in one cell, so a point
// whose key equals the previous keyed point's is marked as a repeat, and the
// caller reuses that point's look-up instead of making its own.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace sarmap {

// Keys computed and prefetched ahead of their look-ups.
inline constexpr std::size_t kPrefetchBatch = 32;

// For each i in [begin, end): key_of(i, key) sets the point's key and
// returns true, or returns false for a point with none (skipped, and not
// counted as the previous point); then visit(i, key, repeat) is called in
// increasing i, `repeat` true when the previous keyed point in the range had
// the same key. `table` is any type with prefetch(key) (FlatKeyIndex,
// LabelledVoxels). key_of runs for a whole batch before visit runs for any
// of it, so neither may depend on the other's effects within a batch.
// key_of answers with a bool and an out-parameter, not a std::optional:
// GCC copies an empty optional through the stack, and the copy's wide load
// stalls on the narrow store just before it, at every skipped point.
template <class Table, class KeyOf, class Visit>
void walk_keys_prefetched(const Table& table, std::size_t begin, std::size_t end, KeyOf&& key_of,
                          Visit&& visit) {
  std::uint64_t keys[kPrefetchBatch];
  bool keyed[kPrefetchBatch];
  std::uint64_t previous_key = 0;
  bool have_previous = false;
  for (std::size_t first = begin; first < end; first += kPrefetchBatch) {
    const std::size_t count = std::min(kPrefetchBatch, end - first);
    for (std::size_t j = 0; j < count; ++j) {
      keyed[j] = key_of(first + j, keys[j]);
      // Every keyed point's slot, a run's repeats too: a branch to skip them
      // is mispredicted more often than a second prefetch of a cached line
      // costs.
      if (keyed[j]) table.prefetch(keys[j]);
    }
    for (std::size_t j = 0; j < count; ++j) {
      if (!keyed[j]) continue;
      const bool repeat = have_previous && keys[j] == previous_key;
      previous_key = keys[j];
      have_previous = true;
      visit(first + j, keys[j], repeat);
    }
  }
}

}  // namespace sarmap
