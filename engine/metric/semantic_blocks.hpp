// The metric map's blocks: SemanticBlock records (semantic_block.hpp) in a
// BlockMap, their log-odds slabs and evidence rows in pools of their own
// (chunk_pool.hpp), and what reads and writes voxels through them. Storage
// is taken and given back here, serially; the integrator writes into what a
// block already holds in parallel (scan_update.cpp: prepare, write, settle).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "engine/metric/block_map.hpp"
#include "engine/metric/chunk_pool.hpp"
#include "engine/metric/semantic_block.hpp"

namespace sarmap::metric {

class SemanticBlocks {
 public:
  using Block = SemanticBlock;
  // The most one block takes: its record, a slab of log-odds, a row of
  // evidence for every voxel, and its share of the key table at its fullest
  // (four 16-byte slots and its key).
  static constexpr std::size_t kMaxBlockBytes = sizeof(SemanticBlock) + kBlockVoxels * sizeof(std::int8_t) +
                                                kBlockVoxels * sizeof(StoredEvidence) + 4 * 16 + 8;

  std::size_t block_count() const { return blocks_.block_count(); }
  bool empty() const { return blocks_.empty(); }

  // The block, or nullptr. One hash look-up.
  const Block* find(const BlockKey& key) const { return blocks_.find(key); }
  Block* find(const BlockKey& key) { return blocks_.find(key); }
  // The block, created all unknown and without evidence if absent.
  Block& find_or_create(const BlockKey& key) { return blocks_.find_or_create(key); }
  // Drops a block (its voxels become unknown) and gives its storage back.
  bool erase(const BlockKey& key);
  // Drops every block and frees all storage.
  void clear() { *this = SemanticBlocks(); }

  // A voxel's value, or nullopt when its block does not exist.
  std::optional<SemanticVoxel> voxel(const VoxelKey& key) const {
    const Block* b = find(block_of(key));
    return b ? std::optional<SemanticVoxel>(b->voxel(local_index(key))) : std::nullopt;
  }
  // Writes one voxel, creating its block. A block left uniform by such
  // writes keeps its slab until the integrator next settles it. Values
  // that do not fit their byte (storable()) throw sarmap::Error
  // (InvalidArgument), as in set_evidence() and assign().
  void set_voxel(const VoxelKey& key, const SemanticVoxel& value);
  // Replaces voxel l's class evidence.
  void set_evidence(Block& block, int l, const ClassEvidence& evidence);
  // Writes a whole block, created if absent, in its compact form.
  void assign(const BlockKey& key, const DenseVoxels& voxels);
  // True when the map can store the value exactly: log-odds within
  // +-kMaxStoredLogOdds or unknown, evidence within +-kMaxEvidence.
  static bool storable(const SemanticVoxel& value) {
    return storable_log_odds(value.log_odds) && storable_evidence(value.evidence);
  }

  // The integrator's update of a block, in three steps: prepare() (serial)
  // expands its occupancy if asked and makes room for new_rows more evidence
  // rows; the update writes within that (in parallel, a block per task);
  // settle() (serial) collapses a block whose log-odds all became equal
  // (uniform_slab(), cheap enough for the parallel step) and gives back
  // evidence storage it no longer needs.
  void prepare(Block& block, bool expand_occupancy, std::size_t new_rows);
  static bool uniform_slab(const Block& block);
  void settle(Block& block, bool uniform);

  // What the blocks allocate, by part (pool pages counted whole, free chunks
  // included); memory_bytes() is their sum and the object itself.
  struct Memory {
    std::size_t records = 0;   // block records, in pages
    std::size_t index = 0;     // the hash table from block keys to records
    std::size_t log_odds = 0;  // slabs of blocks whose log-odds are not uniform
    std::size_t evidence = 0;  // rows of class evidence
  };
  Memory memory() const {
    return {blocks_.record_bytes(), blocks_.index_bytes(), occupancy_.memory_bytes(),
            evidence_.memory_bytes()};
  }
  std::size_t memory_bytes() const {
    const Memory m = memory();
    return sizeof(*this) + m.records + m.index + m.log_odds + m.evidence;
  }
  // Log-odds slabs in use: blocks whose occupancy is not uniform.
  std::size_t slabs_in_use() const { return occupancy_.chunks_in_use(); }

  // Calls fn(BlockKey, const Block&) for every block in unspecified order.
  template <class Fn>
  void for_each_block(Fn&& fn) const {
    blocks_.for_each_block(fn);
  }
  // Block keys in (z, y, x) order: the deterministic order files are written in.
  std::vector<BlockKey> sorted_block_keys() const { return blocks_.sorted_block_keys(); }

  // Caches the last block looked up, so a walk through one block pays one
  // hash look-up. Safe to use from many threads while nothing writes; valid
  // until a block is erased or the map cleared.
  class ConstAccessor {
   public:
    explicit ConstAccessor(const SemanticBlocks& blocks) : blocks_(&blocks) {}
    // A voxel's value, or nullopt when its block does not exist.
    std::optional<SemanticVoxel> find(const VoxelKey& key) {
      const Block* b = block(key);
      return b ? std::optional<SemanticVoxel>(b->voxel(local_index(key))) : std::nullopt;
    }
    // The block holding a voxel, or nullptr.
    const Block* block(const VoxelKey& key) {
      const std::uint64_t word = pack(block_of(key));
      if (word != cached_key_) {
        ++lookups_;
        cached_key_ = word;
        cached_ = blocks_->find(block_of(key));
      }
      return cached_;
    }
    // Number of hash look-ups made (tests check the caching).
    std::size_t lookups() const { return lookups_; }

   private:
    const SemanticBlocks* blocks_;
    std::uint64_t cached_key_ = ~std::uint64_t{0};  // no packed key has all 64 bits set
    const Block* cached_ = nullptr;
    std::size_t lookups_ = 0;
  };

 private:
  using EvidencePool = SizeClassPool<StoredEvidence, kBlockVoxels>;

  void expand(Block& block);
  // Gives back the block's slab and rows storage; the record becomes empty.
  void release(Block& block);
  void reserve_rows(Block& block, std::size_t rows);
  // Gives back rows storage that is empty or four times what is needed.
  void fit_rows(Block& block);

  BlockMap<SemanticBlock> blocks_;
  ChunkPool<std::int8_t> occupancy_{kBlockVoxels};
  EvidencePool evidence_;
};

}  // namespace sarmap::metric
