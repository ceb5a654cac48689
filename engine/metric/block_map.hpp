// A sparse voxel grid: 8 x 8 x 8-voxel blocks in a hash table keyed by block
// coordinates, generic over the voxel payload, with an accessor that caches
// the last block so a walk through one block pays one hash look-up.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "engine/metric/voxel_key.hpp"

namespace sarmap::metric {

// A default-constructed Payload must mean "unknown".
template <class Payload>
struct VoxelBlock {
  std::array<Payload, kBlockVoxels> voxels{};
};

// Blocks live behind unique_ptr so their addresses survive rehashing: an
// accessor's cached pointer and the integrator's per-scan block list stay
// valid while blocks are added (not after erase or clear).
template <class Payload>
class BlockMap {
 public:
  using Block = VoxelBlock<Payload>;

  BlockMap() = default;

  std::size_t block_count() const { return blocks_.size(); }
  bool empty() const { return blocks_.empty(); }

  // The block, or nullptr. One hash look-up.
  Block* find(const BlockKey& key) {
    const auto it = blocks_.find(pack(key));
    return it == blocks_.end() ? nullptr : it->second.get();
  }
  const Block* find(const BlockKey& key) const {
    const auto it = blocks_.find(pack(key));
    return it == blocks_.end() ? nullptr : it->second.get();
  }
  // The block, created all-unknown if absent. Not thread-safe.
  Block& find_or_create(const BlockKey& key) {
    auto& slot = blocks_[pack(key)];
    if (!slot) slot = std::make_unique<Block>();
    return *slot;
  }
  bool erase(const BlockKey& key) { return blocks_.erase(pack(key)) > 0; }
  void clear() { blocks_.clear(); }
  // Bytes the map allocates: every block, its hash node (key, the block's
  // pointer, the next link and the cached hash code, as libstdc++ lays a
  // node out) and the bucket array.
  std::size_t memory_bytes() const {
    constexpr std::size_t node =
        sizeof(void*) + sizeof(std::uint64_t) + sizeof(std::unique_ptr<Block>) + sizeof(std::size_t);
    return sizeof(*this) + blocks_.size() * (sizeof(Block) + node) + blocks_.bucket_count() * sizeof(void*);
  }

  // Payload of a voxel, or nullptr when its block does not exist.
  const Payload* voxel(const VoxelKey& key) const {
    const Block* b = find(block_of(key));
    return b ? &b->voxels[local_index(key)] : nullptr;
  }

  // Calls fn(BlockKey, Block&) for every block in unspecified order.
  template <class Fn>
  void for_each_block(Fn&& fn) {
    for (auto& [word, block] : blocks_) fn(unpack_block(word), *block);
  }
  template <class Fn>
  void for_each_block(Fn&& fn) const {
    for (const auto& [word, block] : blocks_) fn(unpack_block(word), static_cast<const Block&>(*block));
  }
  // Block keys in (z, y, x) order: the deterministic order files are written in.
  std::vector<BlockKey> sorted_block_keys() const {
    std::vector<BlockKey> keys;
    keys.reserve(blocks_.size());
    for (const auto& entry : blocks_) keys.push_back(unpack_block(entry.first));
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
  std::unordered_map<std::uint64_t, std::unique_ptr<Block>, PackedKeyHash> blocks_;
};

}  // namespace sarmap::metric
