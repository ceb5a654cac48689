// An open-addressing set of packed 64-bit keys (metric::pack's 63 bits):
// the Mapper's voxels that hold a kept semantic point. Where FlatKeyIndex
// also numbers its keys (a 16-byte slot and a key list beside the table),
// a slot here is the key alone, so the same keys take less than half the
// bytes; the set only grows and is looked up, and a caller that forgets
// keys builds a new one. Linear probing with FlatKeyIndex's mix_key.
#pragma once

#include <cstddef>
#include <cstdint>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/flat_key_index.hpp"
#include "engine/core/huge_page_allocator.hpp"

namespace sarmap {

class FlatKeySet {
 public:
  // No packed key has its top bit set, so this value marks an empty slot.
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  explicit FlatKeySet(std::size_t initial_capacity = 1024) { rehash(power_of_two_slots(initial_capacity * 2)); }

  std::size_t size() const { return size_; }
  // Bytes held: the slots, by capacity.
  std::size_t memory_bytes() const { return capacity_bytes(slots_); }

  bool contains(std::uint64_t key) const {
    for (std::size_t slot = mix_key(key) & mask_;; slot = (slot + 1) & mask_) {
      if (slots_[slot] == key) return true;
      if (slots_[slot] == kEmpty) return false;
    }
  }
  // Adds key; true when it was not held before. kEmpty is not a key.
  bool insert(std::uint64_t key) {
    for (std::size_t slot = mix_key(key) & mask_;; slot = (slot + 1) & mask_) {
      if (slots_[slot] == key) return false;
      if (slots_[slot] != kEmpty) continue;
      if ((size_ + 1) * 2 > slots_.size()) {
        rehash(slots_.size() * 2);
        return insert(key);
      }
      slots_[slot] = key;
      ++size_;
      return true;
    }
  }
  // Starts loading key's home slot into the cache (walk_keys_prefetched).
  void prefetch(std::uint64_t key) const { __builtin_prefetch(&slots_[mix_key(key) & mask_]); }

 private:
  void rehash(std::size_t capacity) {
    HugePageVector<std::uint64_t> old;
    old.swap(slots_);
    slots_.assign(capacity, kEmpty);
    mask_ = capacity - 1;
    for (const std::uint64_t key : old) {
      if (key == kEmpty) continue;
      std::size_t slot = mix_key(key) & mask_;
      while (slots_[slot] != kEmpty) slot = (slot + 1) & mask_;
      slots_[slot] = key;
    }
  }

  // A large set grows without a page fault per 4 KiB (huge_page_allocator.hpp).
  HugePageVector<std::uint64_t> slots_;
  std::size_t mask_ = 0;
  std::size_t size_ = 0;
};

}  // namespace sarmap
