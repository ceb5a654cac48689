// A sparse voxel grid: 8 x 8 x 8-voxel blocks in pooled storage, found
// through a flat hash table from block keys to block indices, generic over
// the voxel payload, with an accessor that caches the last block so a walk
// through one block pays one hash look-up.
#pragma once

#include <algorithm>
#include <array>
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

// A default-constructed Payload must mean "unknown".
template <class Payload>
struct VoxelBlock {
  std::array<Payload, kBlockVoxels> voxels{};
};

// Blocks are numbered 0..n-1 by the key index (FlatKeyIndex) and stored in
// pages of kPageBlocks, so a new block costs no allocation of its own (one
// per page) and a block's address survives the map's growth: an accessor's
// cached pointer and the integrator's per-scan block list stay valid while
// blocks are added (not after erase or clear). An erase moves the last
// block into the freed index, so storage stays packed, dropped blocks'
// slots are the next ones used, and a page left empty is freed.
template <class Payload>
class BlockMap {
 public:
  using Block = VoxelBlock<Payload>;
  // At most 64 KiB of blocks per page (8 of 7 KiB blocks): few allocations,
  // and little left unused in the last page. A power of two, so a block
  // index splits into page and slot by shift and mask.
  static constexpr std::size_t kPageBlocks =
      std::bit_floor(std::max<std::size_t>(1, (64 << 10) / sizeof(Block)));

  BlockMap() = default;

  std::size_t block_count() const { return index_.size(); }
  bool empty() const { return index_.size() == 0; }

  // The block, or nullptr. One hash look-up.
  Block* find(const BlockKey& key) {
    const std::uint32_t i = index_.find(pack(key));
    return i == FlatKeyIndex::kAbsent ? nullptr : &at(i);
  }
  const Block* find(const BlockKey& key) const {
    const std::uint32_t i = index_.find(pack(key));
    return i == FlatKeyIndex::kAbsent ? nullptr : &at(i);
  }
  // The block, created all-unknown if absent. Not thread-safe.
  Block& find_or_create(const BlockKey& key) {
    const std::size_t count = index_.size();
    const std::uint32_t i = index_.find_or_insert(pack(key));
    // Slots past the last block are kept unknown (erase resets the one it
    // vacates; a new page is value-initialised), so a new block needs no reset.
    if (i == count && i == pages_.size() * kPageBlocks)
      pages_.push_back(std::make_unique<Block[]>(kPageBlocks));
    return at(i);
  }
  // Drops a block: its voxels become unknown, as if never observed. Moves
  // the last block into its slot (invalidating pointers to that block).
  bool erase(const BlockKey& key) {
    const std::uint32_t freed = index_.erase(pack(key));
    if (freed == FlatKeyIndex::kAbsent) return false;
    const std::size_t last = index_.size();  // the moved block's old index
    if (freed != last) at(freed) = at(last);
    at(last).voxels.fill(Payload{});
    pages_.resize((last + kPageBlocks - 1) / kPageBlocks);
    return true;
  }
  // Drops every block and frees all storage.
  void clear() { *this = BlockMap(); }

  // Bytes the map allocates: the pages of blocks (unused slots of the last
  // page included), the page list, and the key index's slots and keys. The
  // index keeps the size it grew to when blocks are dropped.
  std::size_t memory_bytes() const {
    return sizeof(*this) + pages_.size() * kPageBlocks * sizeof(Block) + capacity_bytes(pages_) +
           index_.memory_bytes();
  }

  // Payload of a voxel, or nullptr when its block does not exist.
  const Payload* voxel(const VoxelKey& key) const {
    const Block* b = find(block_of(key));
    return b ? &b->voxels[local_index(key)] : nullptr;
  }

  // Calls fn(BlockKey, Block&) for every block in unspecified order.
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

  // Caches the last block touched; valid until a block is erased or the map cleared.
  class Accessor {
   public:
    explicit Accessor(BlockMap& map) : map_(&map) {}
    // Payload of a voxel, or nullptr if its block does not exist (never creates).
    Payload* find(const VoxelKey& key) {
      Block* b = block(block_of(key), false);
      return b ? &b->voxels[local_index(key)] : nullptr;
    }
    // Payload of a voxel, creating its block (all unknown) when needed.
    Payload& get_or_create(const VoxelKey& key) { return block(block_of(key), true)->voxels[local_index(key)]; }
    // Number of hash look-ups this accessor made (tests check the caching).
    std::size_t lookups() const { return lookups_; }

   private:
    Block* block(const BlockKey& key, bool create) {
      const std::uint64_t word = pack(key);
      if (word == cached_key_ && (cached_ || !create)) return cached_;
      ++lookups_;
      cached_key_ = word;
      cached_ = create ? &map_->find_or_create(key) : map_->find(key);
      return cached_;
    }
    BlockMap* map_;
    std::uint64_t cached_key_ = ~std::uint64_t{0};  // no packed key has all 64 bits set
    Block* cached_ = nullptr;
    std::size_t lookups_ = 0;
  };

  // Read-only accessor; safe to use from many threads while nothing writes.
  class ConstAccessor {
   public:
    explicit ConstAccessor(const BlockMap& map) : map_(&map) {}
    const Payload* find(const VoxelKey& key) {
      const std::uint64_t word = pack(block_of(key));
      if (word != cached_key_) {
        ++lookups_;
        cached_key_ = word;
        cached_ = map_->find(block_of(key));
      }
      return cached_ ? &cached_->voxels[local_index(key)] : nullptr;
    }
    std::size_t lookups() const { return lookups_; }

   private:
    const BlockMap* map_;
    std::uint64_t cached_key_ = ~std::uint64_t{0};
    const Block* cached_ = nullptr;
    std::size_t lookups_ = 0;
  };

 private:
  static constexpr int kPageShift = std::countr_zero(kPageBlocks);

  Block& at(std::size_t i) { return pages_[i >> kPageShift][i & (kPageBlocks - 1)]; }
  const Block& at(std::size_t i) const { return pages_[i >> kPageShift][i & (kPageBlocks - 1)]; }

  // Small at first: a map of a few blocks (tests, a hand-made map) should
  // not pay for a large table; it doubles as blocks are added.
  FlatKeyIndex index_{64};
  std::vector<std::unique_ptr<Block[]>> pages_;
};

}  // namespace sarmap::metric
