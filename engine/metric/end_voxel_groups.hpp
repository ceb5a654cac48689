// The distinct voxels a scan's points end in, with what those points say
// about each voxel's class: the end-voxel dedupe of ray integration (each
// voxel is cast once and updated once per scan). Two steps:
//  - LocalEndGroups, in parallel over fixed stretches of points: fold each
//    point into the group of its voxel, found through a small direct-mapped
//    cache of recent voxels. Neighbouring points of a depth image mostly
//    share voxels, so most points fold into an existing group; a voxel that
//    fell out of the cache opens another group, which the merge adds up.
//  - EndVoxelGroups::merge, serially over the stretches' groups in order:
//    one group per voxel, found through a dense table over the box of the
//    scan's end voxels when the box is small enough, else through a hash table.
// Float sums of class scores are added in an order fixed by the stretches,
// so the result depends neither on the thread count nor on the table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "engine/core/point_buffer.hpp"
#include "engine/core/flat_key_index.hpp"
#include "engine/core/huge_page_allocator.hpp"
#include "engine/metric/label_fusion.hpp"
#include "engine/metric/voxel_key.hpp"

namespace sarmap::metric {

// Inclusive box of voxel keys.
struct VoxelBox {
  VoxelKey lo{std::numeric_limits<std::int32_t>::max(), std::numeric_limits<std::int32_t>::max(),
              std::numeric_limits<std::int32_t>::max()};
  VoxelKey hi{std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::min(),
              std::numeric_limits<std::int32_t>::min()};

  bool empty() const { return lo.x > hi.x; }
  // Inline: called once per point.
  void add(const VoxelKey& k) {
    lo = {k.x < lo.x ? k.x : lo.x, k.y < lo.y ? k.y : lo.y, k.z < lo.z ? k.z : lo.z};
    hi = {k.x > hi.x ? k.x : hi.x, k.y > hi.y ? k.y : hi.y, k.z > hi.z ? k.z : hi.z};
  }
  void add(const VoxelBox& b) {
    if (b.empty()) return;
    add(b.lo);
    add(b.hi);
  }
  // Cells in the box (0 when empty); saturates instead of overflowing.
  std::size_t cells() const;
};

// Where a point's class observation comes from: per-class score channels
// (by class id) when there are any, else the labels, else class 0.
struct ClassSource {
  std::vector<std::span<const float>> scores;
  std::span<const std::uint8_t> labels;

  // Scores when use_scores and points has a score channel named after every class.
  static ClassSource of(const PointBuffer& points, bool use_scores);
};

class LocalEndGroups {
 public:
  LocalEndGroups();
  // Forgets the groups and the cache.
  void clear();
  // Folds point i, whose voxel's packed key (pack()) is key, into a group.
  // Inline: once per point.
  void add(std::uint64_t key, std::size_t i, const ClassSource& source) {
    observe(observations_[group_of(key)], i, source);
  }
  // add() for a source without scores, given the point's hard label (0
  // without labels). Inline: once per point, the common case, with nothing
  // of the source to re-read after each counter store.
  void add_labelled(std::uint64_t key, std::uint8_t label) {
    ClassObservation& obs = observations_[group_of(key)];
    ++obs.points;
    if (obs.counts[label] < 0xffff) ++obs.counts[label];
  }

  const std::vector<VoxelKey>& keys() const { return keys_; }
  const std::vector<ClassObservation>& observations() const { return observations_; }
  const VoxelBox& box() const { return box_; }
  // Bytes held (the cache and the groups, by capacity).
  std::size_t memory_bytes() const;

 private:
  // Packed keys use 63 bits (pack()), so the all-ones word marks an empty slot.
  static constexpr std::uint64_t kEmptySlot = ~std::uint64_t{0};
  static constexpr int kCacheBits = 10;
  struct Slot {
    std::uint64_t key = kEmptySlot;
    std::uint32_t group = 0;
  };
  // The group of a voxel, opened if the cache does not hold it. Inline: once per point.
  std::uint32_t group_of(std::uint64_t key) {
    Slot& slot = cache_[cache_slot(key)];
    if (slot.key != key) {  // an empty slot holds kEmptySlot, which no voxel packs to
      slot.key = key;
      slot.group = static_cast<std::uint32_t>(keys_.size());
      const VoxelKey voxel = unpack_voxel(key);
      keys_.push_back(voxel);
      observations_.emplace_back();
      box_.add(voxel);
    }
    return slot.group;
  }
  // Fibonacci hashing: the top bits of the product depend on every key bit.
  static std::size_t cache_slot(std::uint64_t key) {
    return static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ull) >> (64 - kCacheBits));
  }
  // Inline: called once per point.
  static void observe(ClassObservation& obs, std::size_t i, const ClassSource& source) {
    ++obs.points;
    std::size_t label = 0;
    if (!source.scores.empty()) {
      obs.has_scores = true;
      float best = -1.0f;
      for (std::size_t c = 0; c < kClassCount; ++c) {
        const float s = source.scores[c][i];
        obs.score_sums[c] += s;
        if (s > best) best = s, label = c;
      }
    } else if (!source.labels.empty()) {
      label = source.labels[i];
    }
    if (obs.counts[label] < 0xffff) ++obs.counts[label];
  }

  std::vector<Slot> cache_;
  std::vector<VoxelKey> keys_;
  std::vector<ClassObservation> observations_;
  VoxelBox box_;
};

class EndVoxelGroups {
 public:
  // One group per voxel of the stretches' groups, in order of first
  // appearance; the dense table is used when the box of all their voxels
  // has at most max_dense_cells cells. progress(n), if given, is called with
  // the number of groups so far after every kProgressGroups new groups and
  // after each stretch: the keys below n are final and stay where they are
  // until the next merge, so another thread may read them while the merge
  // goes on (their observations may still grow: a later stretch can see the
  // same voxel).
  static constexpr std::size_t kProgressGroups = 256;
  void merge(std::span<const LocalEndGroups> stretches, std::size_t max_dense_cells,
             const std::function<void(std::size_t)>& progress = {});

  std::size_t size() const { return keys_.size(); }
  const HugePageVector<VoxelKey>& keys() const { return keys_; }
  const HugePageVector<ClassObservation>& observations() const { return observations_; }
  // Whether the last merge() used the dense table (for tests).
  bool used_dense_table() const { return used_dense_; }
  // Bytes held (groups, hash table and dense table, by capacity).
  std::size_t memory_bytes() const;

 private:
  // Scratch in whole huge pages (reserve_whole_huge_pages): a fresh
  // process's first scans would otherwise fault them in a page at a time.
  HugePageVector<VoxelKey> keys_;
  HugePageVector<ClassObservation> observations_;
  FlatKeyIndex hashed_{65536};
  // Dense table: group index + 1 per cell of the box, 0 for none; all zero
  // between calls (merge() resets the cells it used).
  HugePageVector<std::uint32_t> dense_;
  bool used_dense_ = false;
};

}  // namespace sarmap::metric
