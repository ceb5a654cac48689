#include "engine/metric/semantic_blocks.hpp"

#include <algorithm>
#include <cstring>

namespace sarmap::metric {

bool SemanticBlocks::erase(const BlockKey& key) {
  Block* block = blocks_.find(key);
  if (block == nullptr) return false;
  release(*block);
  return blocks_.erase(key);
}

void SemanticBlocks::set_voxel(const VoxelKey& key, const SemanticVoxel& value) {
  Block& block = find_or_create(block_of(key));
  const int l = local_index(key);
  if (block.uniform_occupancy() && value.log_odds != block.uniform_) expand(block);
  if (!block.uniform_occupancy()) block.log_odds_[l] = value.log_odds;
  set_evidence(block, l, value.evidence);
}

void SemanticBlocks::set_evidence(Block& block, int l, const ClassEvidence& evidence) {
  if (!no_evidence(evidence) && !block.holds_evidence(l))
    reserve_rows(block, block.row_count_ + std::size_t{1});
  block.put_evidence(l, evidence);
  fit_rows(block);
}

void SemanticBlocks::assign(const BlockKey& key, const DenseVoxels& voxels) {
  Block& block = find_or_create(key);
  release(block);
  const std::int16_t first = voxels[0].log_odds;
  const bool uniform = std::all_of(voxels.begin(), voxels.end(),
                                   [first](const SemanticVoxel& v) { return v.log_odds == first; });
  block.uniform_ = first;
  if (!uniform) {
    expand(block);
    for (int l = 0; l < kBlockVoxels; ++l) block.log_odds_[l] = voxels[l].log_odds;
  }
  const auto rows = static_cast<std::size_t>(std::count_if(
      voxels.begin(), voxels.end(), [](const SemanticVoxel& v) { return !no_evidence(v.evidence); }));
  reserve_rows(block, rows);
  // In voxel order, each row goes at the end: no rows move.
  for (int l = 0; l < kBlockVoxels; ++l) block.put_evidence(l, voxels[l].evidence);
}

void SemanticBlocks::prepare(Block& block, bool expand_occupancy, std::size_t new_rows) {
  if (expand_occupancy && block.uniform_occupancy()) expand(block);
  reserve_rows(block, block.row_count_ + new_rows);
}

bool SemanticBlocks::uniform_slab(const Block& block) {
  const std::int16_t* slab = block.log_odds_;
  if (slab == nullptr) return true;
  // Differences ORed together: a loop the compiler vectorises, no early exit.
  int differ = 0;
  for (int l = 1; l < kBlockVoxels; ++l) differ |= slab[l] ^ slab[0];
  return differ == 0;
}

void SemanticBlocks::settle(Block& block, bool uniform) {
  if (uniform && !block.uniform_occupancy()) {
    block.uniform_ = block.log_odds_[0];
    occupancy_.give(block.log_odds_);
    block.log_odds_ = nullptr;
  }
  fit_rows(block);
}

void SemanticBlocks::expand(Block& block) {
  std::int16_t* slab = occupancy_.take();
  std::fill(slab, slab + kBlockVoxels, block.uniform_);
  block.log_odds_ = slab;
}

void SemanticBlocks::release(Block& block) {
  if (block.log_odds_ != nullptr) occupancy_.give(block.log_odds_);
  if (block.rows_ != nullptr) evidence_.give(block.rows_, block.row_capacity_);
  block = Block{};
}

void SemanticBlocks::reserve_rows(Block& block, std::size_t rows) {
  if (rows <= block.row_capacity_) return;
  const std::size_t capacity = EvidencePool::capacity_for(rows);
  ClassEvidence* chunk = evidence_.take(capacity);
  if (block.row_count_ > 0) std::memcpy(chunk, block.rows_, block.row_count_ * sizeof(ClassEvidence));
  if (block.rows_ != nullptr) evidence_.give(block.rows_, block.row_capacity_);
  block.rows_ = chunk;
  block.row_capacity_ = static_cast<std::uint16_t>(capacity);
}

void SemanticBlocks::fit_rows(Block& block) {
  if (block.rows_ == nullptr) return;
  if (block.row_count_ == 0) {
    evidence_.give(block.rows_, block.row_capacity_);
    block.rows_ = nullptr;
    block.row_capacity_ = 0;
    return;
  }
  // Shrinks to twice what is needed, so rows coming back soon fit.
  const std::size_t needed = EvidencePool::capacity_for(block.row_count_);
  if (block.row_capacity_ < 4 * needed) return;
  const std::size_t capacity = 2 * needed;
  ClassEvidence* chunk = evidence_.take(capacity);
  std::memcpy(chunk, block.rows_, block.row_count_ * sizeof(ClassEvidence));
  evidence_.give(block.rows_, block.row_capacity_);
  block.rows_ = chunk;
  block.row_capacity_ = static_cast<std::uint16_t>(capacity);
}

}  // namespace sarmap::metric
