// A sparse grid of 8 x 8 x 8-voxel blocks: fixed-size block records in
// pooled storage, found through a flat hash table from block keys to block
// indices. Generic over the record; the metric map's is SemanticBlock, which
// keeps its voxels in pools of its own (semantic_blocks.hpp).
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <tuple>
#include <vector>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/flat_key_index.hpp"
#include "engine/metric/voxel_key.hpp"

namespace sarmap::metric {

// Records are numbered 0..n-1 by the key index (FlatKeyIndex) and stored in
// pages of kPageBlocks, so a new block costs no allocation of its own (one
// per page) and a record's address survives the map's growth: a cached
// pointer stays valid while blocks are added (not after erase or clear). An
// erase moves the last record into the freed index, so storage stays packed,
// dropped blocks' slots are the next ones used, and a page left empty is
// freed. A default-constructed Record is an empty block.
template <class Record>
class BlockMap {
 public:
  // At most 16 KiB of records per page: few allocations, little left unused
  // in the last page. A power of two, so a block index splits into page and
  // slot by shift and mask.
  static constexpr std::size_t kPageBlocks =
      std::bit_floor(std::max<std::size_t>(1, (16 << 10) / sizeof(Record)));

  std::size_t block_count() const { return index_.size(); }
  bool empty() const { return index_.size() == 0; }

  // The block, or nullptr. One hash look-up.
  Record* find(const BlockKey& key) {
    const std::uint32_t i = index_.find(pack(key));
    return i == FlatKeyIndex::kAbsent ? nullptr : &at(i);
  }
  const Record* find(const BlockKey& key) const {
    const std::uint32_t i = index_.find(pack(key));
    return i == FlatKeyIndex::kAbsent ? nullptr : &at(i);
  }
  // The block, created empty if absent. Not thread-safe.
  Record& find_or_create(const BlockKey& key) {
    const std::size_t count = index_.size();
    const std::uint32_t i = index_.find_or_insert(pack(key));
    // Slots past the last block are kept empty (erase resets the one it
    // vacates; a new page is value-initialised), so a new block needs no reset.
    if (i == count && i == pages_.size() * kPageBlocks)
      pages_.push_back(std::make_unique<Record[]>(kPageBlocks));
    return at(i);
  }
  // Drops a block. Moves the last block's record into its slot
  // (invalidating pointers to that record).
  bool erase(const BlockKey& key) {
    const std::uint32_t freed = index_.erase(pack(key));
    if (freed == FlatKeyIndex::kAbsent) return false;
    const std::size_t last = index_.size();  // the moved record's old index
    if (freed != last) at(freed) = at(last);
    at(last) = Record{};
    pages_.resize((last + kPageBlocks - 1) / kPageBlocks);
    return true;
  }
  // Drops every block and frees all storage.
  void clear() { *this = BlockMap(); }

  // Bytes the map allocates: record_bytes() and index_bytes() and the map object.
  std::size_t memory_bytes() const { return sizeof(*this) + record_bytes() + index_bytes(); }
  // The pages of records (unused slots of the last page included) and the page list.
  std::size_t record_bytes() const {
    return pages_.size() * kPageBlocks * sizeof(Record) + capacity_bytes(pages_);
  }
  // The key index's slots and keys; it keeps the size it grew to when blocks are dropped.
  std::size_t index_bytes() const { return index_.memory_bytes(); }

  // Calls fn(BlockKey, Record&) for every block in unspecified order.
  template <class Fn>
  void for_each_block(Fn&& fn) {
    const std::vector<std::uint64_t>& keys = index_.keys();
    for (std::size_t i = 0; i < keys.size(); ++i) fn(unpack_block(keys[i]), at(i));
  }
  template <class Fn>
  void for_each_block(Fn&& fn) const {
    const std::vector<std::uint64_t>& keys = index_.keys();
    for (std::size_t i = 0; i < keys.size(); ++i) fn(unpack_block(keys[i]), at(i));
  }
  // Block keys in (z, y, x) order: the deterministic order files are written in.
  std::vector<BlockKey> sorted_block_keys() const {
    std::vector<BlockKey> keys;
    keys.reserve(index_.size());
    for (const std::uint64_t word : index_.keys()) keys.push_back(unpack_block(word));
    std::sort(keys.begin(), keys.end(), [](const BlockKey& a, const BlockKey& b) {
      return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x);
    });
    return keys;
  }

 private:
  static constexpr int kPageShift = std::countr_zero(kPageBlocks);

  Record& at(std::size_t i) { return pages_[i >> kPageShift][i & (kPageBlocks - 1)]; }
  const Record& at(std::size_t i) const { return pages_[i >> kPageShift][i & (kPageBlocks - 1)]; }

  // Small at first: a map of a few blocks (tests, a hand-made map) should
  // not pay for a large table; it doubles as blocks are added.
  FlatKeyIndex index_{64};
  std::vector<std::unique_ptr<Record[]>> pages_;
};

}  // namespace sarmap::metric
