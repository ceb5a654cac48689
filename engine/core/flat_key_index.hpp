// An open-addressing table from packed 64-bit keys to dense indices 0..n-1 in
// insertion order: the metric integrator's per-scan scratch (end-voxel
// dedupe, the blocks a thread's rays touch), the segment map's voxel index,
// the metric map's index of its pooled blocks (block_map.hpp), the labelled
// point map's cells, and through FlatKeyMap
// (flat_key_map.hpp) the grid tables of the label rules, the surface normals
// and the topological map.
// Hand-written because it sits in the ray loop and
// bench/metric/key_table_bench.cpp measures it against std::unordered_map and
// tbb::concurrent_hash_map on the same look-up stream. Linear probing, so an
// erase shifts the entries after it back instead of leaving tombstones, and
// the last key takes the erased key's index, so indices stay dense and a
// caller's arrays indexed by them stay packed. A set of keys that needs no
// indices is a FlatKeySet (flat_key_set.hpp), in less than half the bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/huge_page_allocator.hpp"

namespace sarmap {

// Finalizer of splitmix64: packed keys differ in few low bits, so they need
// full avalanche before a power-of-two table masks them.
inline std::uint64_t mix_key(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

// Slots for a table to hold n: a power of two (so that masking a mixed key
// finds its home slot), at least 16.
inline std::size_t power_of_two_slots(std::size_t n) {
  std::size_t p = 16;
  while (p < n) p *= 2;
  return p;
}

class FlatKeyIndex {
 public:
  static constexpr std::uint32_t kAbsent = 0xffffffffu;

  explicit FlatKeyIndex(std::size_t initial_capacity = 1024) { rehash(power_of_two_slots(initial_capacity * 2)); }

  std::size_t size() const { return keys_.size(); }
  // Bytes held: the slots and the key list, by capacity.
  std::size_t memory_bytes() const { return capacity_bytes(slots_) + capacity_bytes(keys_); }
  // Keys in insertion order; key i has index i.
  const std::vector<std::uint64_t>& keys() const { return keys_; }

  // Index of key, inserting it with the next index if absent.
  std::uint32_t find_or_insert(std::uint64_t key) {
    std::size_t slot = mix_key(key) & mask_;
    while (true) {
      Slot& s = slots_[slot];
      if (s.index != kAbsent && s.key == key) return s.index;
      if (s.index == kAbsent) {
        if ((keys_.size() + 1) * 2 > slots_.size()) {
          rehash(slots_.size() * 2);
          return find_or_insert(key);
        }
        s.key = key;
        s.index = static_cast<std::uint32_t>(keys_.size());
        keys_.push_back(key);
        return s.index;
      }
      slot = (slot + 1) & mask_;
    }
  }
  // Starts loading key's home slot into the cache and returns at once. A
  // loop that looks up keys scattered over a large table prefetches a batch
  // of them before finding them (walk_keys_prefetched), so that their
  // cache misses overlap instead of waiting one after another. Only a hint:
  // it changes nothing.
  void prefetch(std::uint64_t key) const { __builtin_prefetch(&slots_[mix_key(key) & mask_]); }
  // Index of key, or kAbsent.
  std::uint32_t find(std::uint64_t key) const {
    std::size_t slot = mix_key(key) & mask_;
    while (true) {
      const Slot& s = slots_[slot];
      if (s.index == kAbsent) return kAbsent;
      if (s.key == key) return s.index;
      slot = (slot + 1) & mask_;
    }
  }
  // Removes key. The key with the last index (size() - 1) takes its index,
  // so the caller moves its entry at size() (after the call) to the index
  // returned; nothing moves when the removed key had the last index.
  // Returns the removed key's index, or kAbsent if the key was not held.
  std::uint32_t erase(std::uint64_t key) {
    const std::size_t slot = slot_of(key);
    if (slot == kNoSlot) return kAbsent;
    const std::uint32_t index = slots_[slot].index;
    const std::uint32_t last = static_cast<std::uint32_t>(keys_.size() - 1);
    if (index != last) {
      slots_[slot_of(keys_[last])].index = index;
      keys_[index] = keys_[last];
    }
    keys_.pop_back();
    // Backward shift: each later entry of the run moves into the hole unless
    // the hole lies before its home slot (cyclically), where a probe from
    // its home would not pass.
    std::size_t hole = slot;
    for (std::size_t next = (hole + 1) & mask_; slots_[next].index != kAbsent; next = (next + 1) & mask_) {
      const std::size_t home = mix_key(slots_[next].key) & mask_;
      if (((next - home) & mask_) >= ((next - hole) & mask_)) {
        slots_[hole] = slots_[next];
        hole = next;
      }
    }
    slots_[hole].index = kAbsent;
    return index;
  }
  // Empties the table, keeping its capacity. Costs the number of keys held.
  void clear() {
    for (std::uint64_t key : keys_) {
      std::size_t slot = mix_key(key) & mask_;
      while (slots_[slot].key != key || slots_[slot].index == kAbsent) slot = (slot + 1) & mask_;
      slots_[slot].index = kAbsent;
    }
    keys_.clear();
  }

 private:
  static constexpr std::size_t kNoSlot = ~std::size_t{0};
  // An empty slot has index kAbsent; its key is then meaningless.
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t index = kAbsent;
  };

  // The slot holding key, or kNoSlot.
  std::size_t slot_of(std::uint64_t key) const {
    std::size_t slot = mix_key(key) & mask_;
    while (true) {
      const Slot& s = slots_[slot];
      if (s.index == kAbsent) return kNoSlot;
      if (s.key == key) return slot;
      slot = (slot + 1) & mask_;
    }
  }
  void rehash(std::size_t capacity) {
    slots_.assign(capacity, Slot{});
    mask_ = capacity - 1;
    for (std::uint32_t i = 0; i < keys_.size(); ++i) {
      std::size_t slot = mix_key(keys_[i]) & mask_;
      while (slots_[slot].index != kAbsent) slot = (slot + 1) & mask_;
      slots_[slot] = Slot{keys_[i], i};
    }
  }

  // A large table grows without a page fault per 4 KiB (huge_page_allocator.hpp).
  HugePageVector<Slot> slots_;
  std::size_t mask_ = 0;
  std::vector<std::uint64_t> keys_;
};

}  // namespace sarmap
