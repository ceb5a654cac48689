// Fixed-size chunks carved from pages of 16 KiB, with a free list: the storage
// the metric map's blocks take their log-odds and class evidence from
// (semantic_blocks.hpp), so that neither costs an allocation of its own and a
// chunk given back is the next one taken. Pages are never returned before
// the pool is destroyed; memory_bytes() counts them all.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "engine/core/capacity_bytes.hpp"

namespace sarmap::metric {

template <class T>
class ChunkPool {
 public:
  // Small pages: a map of a few blocks pays little for a pool (the evidence
  // has eight), and pages are still few next to the blocks they serve.
  static constexpr std::size_t kPageBytes = std::size_t{16} << 10;

  // Chunks of chunk_size elements; a page holds as many as fit in 16 KiB (at least one).
  explicit ChunkPool(std::size_t chunk_size)
      : chunk_(chunk_size), per_page_(std::max<std::size_t>(1, kPageBytes / (chunk_size * sizeof(T)))) {}

  std::size_t chunk_size() const { return chunk_; }

  // A chunk, its elements as the last user left them (value-initialised
  // when never used). Not thread-safe.
  T* take() {
    if (!free_.empty()) {
      T* chunk = free_.back();
      free_.pop_back();
      return chunk;
    }
    if (used_in_last_ == per_page_) {
      pages_.push_back(std::make_unique<T[]>(per_page_ * chunk_));
      used_in_last_ = 0;
    }
    return pages_.back().get() + chunk_ * used_in_last_++;
  }
  // Gives back a chunk this pool handed out.
  void give(T* chunk) { free_.push_back(chunk); }
  // Chunks handed out and not given back.
  std::size_t chunks_in_use() const {
    return pages_.empty() ? 0 : (pages_.size() - 1) * per_page_ + used_in_last_ - free_.size();
  }

  // Bytes allocated: every page, the page list and the free list.
  std::size_t memory_bytes() const {
    return pages_.size() * per_page_ * chunk_ * sizeof(T) + capacity_bytes(pages_) + capacity_bytes(free_);
  }

 private:
  std::size_t chunk_;
  std::size_t per_page_;
  std::vector<std::unique_ptr<T[]>> pages_;
  std::size_t used_in_last_ = per_page_;
  std::vector<T*> free_;
};

// Chunks of rows in size classes of 4, 8, ..., 512 rows, so a block's rows
// grow by moving to the next class and most of a chunk is in use.
template <class Row, std::size_t kMaxRows>
class SizeClassPool {
 public:
  static constexpr std::size_t kMinRows = 4;

  // Rows of the smallest class that holds n (0 for none); n <= kMaxRows.
  static std::size_t capacity_for(std::size_t n) {
    if (n == 0) return 0;
    std::size_t c = kMinRows;
    while (c < n) c *= 2;
    return c;
  }

  // A chunk of capacity rows, capacity_for() of some n.
  Row* take(std::size_t capacity) { return pool(capacity).take(); }
  void give(Row* chunk, std::size_t capacity) { pool(capacity).give(chunk); }

  std::size_t memory_bytes() const {
    std::size_t bytes = 0;
    for (const auto& p : pools_) bytes += p.memory_bytes();
    return bytes;
  }

 private:
  static constexpr std::size_t class_count() {
    std::size_t n = 1;
    for (std::size_t c = kMinRows; c < kMaxRows; c *= 2) ++n;
    return n;
  }
  static std::size_t class_of(std::size_t capacity) {
    std::size_t k = 0;
    for (std::size_t c = kMinRows; c < capacity; c *= 2) ++k;
    return k;
  }
  ChunkPool<Row>& pool(std::size_t capacity) { return pools_[class_of(capacity)]; }

  template <std::size_t... I>
  static std::array<ChunkPool<Row>, sizeof...(I)> make_pools(std::index_sequence<I...>) {
    return {ChunkPool<Row>(kMinRows << I)...};
  }
  std::array<ChunkPool<Row>, class_count()> pools_ = make_pools(std::make_index_sequence<class_count()>{});
};

}  // namespace sarmap::metric
