// An open-addressing table from packed 64-bit keys to dense indices 0..n-1 in
// insertion order: the metric integrator's per-scan scratch (end-voxel
// dedupe, the blocks a thread's rays touch) and the segment map's voxel index.
// Hand-written because it sits in the ray loop and
// bench/metric/key_table_bench.cpp measures it against std::unordered_map and
// tbb::concurrent_hash_map on the same look-up stream; it only ever grows (or
// is cleared), so it needs no deletion.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/core/capacity_bytes.hpp"

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

class FlatKeyIndex {
 public:
  static constexpr std::uint32_t kAbsent = 0xffffffffu;

  explicit FlatKeyIndex(std::size_t initial_capacity = 1024) { rehash(round_up(initial_capacity * 2)); }

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
  // An empty slot has index kAbsent; its key is then meaningless.
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t index = kAbsent;
  };

  static std::size_t round_up(std::size_t n) {
    std::size_t p = 16;
    while (p < n) p *= 2;
    return p;
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

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  std::vector<std::uint64_t> keys_;
};

}  // namespace sarmap
