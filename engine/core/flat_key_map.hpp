// A FlatKeyIndex with a value per key, the values in one array by index
// (key i's value is values()[i], in insertion order): the grid tables of the
// label rules, the surface normals' cells and the topological map's
// neighbour cells. Callers that walk every entry walk one packed array, and
// an entry's index can stand for it in a caller's own per-point arrays.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/flat_key_index.hpp"

namespace sarmap {

template <class T>
class FlatKeyMap {
 public:
  static constexpr std::uint32_t kAbsent = FlatKeyIndex::kAbsent;

  explicit FlatKeyMap(std::size_t initial_capacity = 1024) : index_(initial_capacity) {}

  std::size_t size() const { return values_.size(); }
  bool empty() const { return values_.empty(); }
  // Bytes held: the index's and the values', by capacity.
  std::size_t memory_bytes() const { return index_.memory_bytes() + capacity_bytes(values_); }
  const std::vector<std::uint64_t>& keys() const { return index_.keys(); }
  std::vector<T>& values() { return values_; }
  const std::vector<T>& values() const { return values_; }

  struct Insertion {
    std::uint32_t index;
    bool inserted;  // the key was new, its value made from the arguments
  };
  // The key's index; a new key's value is made from `args`, a held key's is
  // left as it is (the arguments unused).
  template <class... Args>
  Insertion try_emplace(std::uint64_t key, Args&&... args) {
    const std::uint32_t i = index_.find_or_insert(key);
    if (i < values_.size()) return {i, false};
    values_.emplace_back(std::forward<Args>(args)...);
    return {i, true};
  }
  // The key's value, value-initialised first if the key is new.
  T& operator[](std::uint64_t key) { return values_[try_emplace(key).index]; }

  // The key's index, or kAbsent.
  std::uint32_t index_of(std::uint64_t key) const { return index_.find(key); }
  // The key's value, or nullptr.
  const T* find(std::uint64_t key) const {
    const std::uint32_t i = index_.find(key);
    return i == kAbsent ? nullptr : &values_[i];
  }
  T* find(std::uint64_t key) {
    const std::uint32_t i = index_.find(key);
    return i == kAbsent ? nullptr : &values_[i];
  }

  // Empties the map, keeping the index's capacity.
  void clear() {
    index_.clear();
    values_.clear();
  }

 private:
  FlatKeyIndex index_;
  std::vector<T> values_;
};

}  // namespace sarmap
