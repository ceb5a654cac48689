#include "engine/metric/semantic_blocks.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::metric {

namespace {
void require_storable(const SemanticVoxel& value) {
  if (SemanticBlocks::storable(value)) return;
  std::string evidence;
  for (std::int16_t e : value.evidence) evidence += (evidence.empty() ? "" : ", ") + std::to_string(e);
  throw Error(ErrorCode::InvalidArgument,
              "metric map: voxel value out of range (log-odds " + std::to_string(value.log_odds) +
                  ", evidence [" + evidence + "]; known log-odds lie within +-" +
                  std::to_string(kMaxStoredLogOdds) + ", evidence within +-" + std::to_string(kMaxEvidence) + ")");
}
}  // namespace

bool SemanticBlocks::erase(const BlockKey& key) {
  Block* block = blocks_.find(key);
  if (block == nullptr) return false;
  release(*block);
  return blocks_.erase(key);
}

void SemanticBlocks::set_voxel(const VoxelKey& key, const SemanticVoxel& value) {
  require_storable(value);
  Block& block = find_or_create(block_of(key));
  const int l = local_index(key);
  if (block.uniform_occupancy() && value.log_odds != block.uniform_) expand(block);
  if (!block.uniform_occupancy()) block.log_odds_[l] = stored_log_odds(value.log_odds);
  set_evidence(block, l, value.evidence);
}

void SemanticBlocks::set_evidence(Block& block, int l, const ClassEvidence& evidence) {
  require_storable({kUnknownLogOdds, evidence});
  if (!no_evidence(evidence) && !block.holds_evidence(l))
    reserve_rows(block, block.row_count_ + std::size_t{1});
  block.put_evidence(l, evidence);
  fit_rows(block);
}

void SemanticBlocks::assign(const BlockKey& key, const DenseVoxels& voxels) {
  for (const SemanticVoxel& v : voxels) require_storable(v);
  Block& block = find_or_create(key);
  release(block);
  const std::int16_t first = voxels[0].log_odds;
  const bool uniform = std::all_of(voxels.begin(), voxels.end(),
                                   [first](const SemanticVoxel& v) { return v.log_odds == first; });
  block.uniform_ = first;
  if (!uniform) {
    expand(block);
    for (int l = 0; l < kBlockVoxels; ++l) block.log_odds_[l] = stored_log_odds(voxels[l].log_odds);
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
  const std::int8_t* slab = block.log_odds_;
  if (slab == nullptr) return true;
  // Differences ORed together: a loop the compiler vectorises, no early exit.
  int differ = 0;
  for (int l = 1; l < kBlockVoxels; ++l) differ |= slab[l] ^ slab[0];
  return differ == 0;
}

void SemanticBlocks::settle(Block& block, bool uniform) {
  if (uniform && !block.uniform_occupancy()) {
    block.uniform_ = log_odds_of(block.log_odds_[0]);
    occupancy_.give(block.log_odds_);
    block.log_odds_ = nullptr;
  }
  fit_rows(block);
}

void SemanticBlocks::expand(Block& block) {
  std::int8_t* slab = occupancy_.take();
  std::fill(slab, slab + kBlockVoxels, stored_log_odds(block.uniform_));
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
  StoredEvidence* chunk = evidence_.take(capacity);
  if (block.row_count_ > 0) std::memcpy(chunk, block.rows_, block.row_count_ * sizeof(StoredEvidence));
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
  StoredEvidence* chunk = evidence_.take(capacity);
  std::memcpy(chunk, block.rows_, block.row_count_ * sizeof(StoredEvidence));
  evidence_.give(block.rows_, block.row_capacity_);
  block.rows_ = chunk;
  block.row_capacity_ = static_cast<std::uint16_t>(capacity);
}

}  // namespace sarmap::metric
