// One 8 x 8 x 8 block of the metric map, stored compactly: its occupancy
// either as one value for the whole block (a block still all unknown, or all
// free at the same log-odds) or as 512 one-byte log-odds in a slab of the
// map's occupancy pool; its class evidence only for the voxels that hold
// some, as rows of six bytes in voxel order in a chunk of the map's evidence
// pool, found through a bit per voxel. The voxels' values are exactly those
// of a dense array of SemanticVoxel, whose every value fits in a byte
// (semantic_voxel.hpp, label_fusion.hpp); only their storage differs
// (docs/architecture.md).
//
// The record is written in two ways: by SemanticBlocks (semantic_blocks.hpp),
// which takes and gives back pool storage, and, within storage already
// taken, by the integrator's parallel update, one block per task.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "engine/metric/label_fusion.hpp"
#include "engine/metric/semantic_voxel.hpp"
#include "engine/metric/voxel_key.hpp"

namespace sarmap::metric {

// A voxel's class evidence as its row stores it, a byte per class.
using StoredEvidence = std::array<std::int8_t, kClassCount>;
inline StoredEvidence stored_evidence(const ClassEvidence& e) {
  StoredEvidence out;
  for (std::size_t c = 0; c < kClassCount; ++c) out[c] = static_cast<std::int8_t>(e[c]);
  return out;
}
inline ClassEvidence evidence_of(const StoredEvidence& stored) {
  ClassEvidence out;
  for (std::size_t c = 0; c < kClassCount; ++c) out[c] = stored[c];
  return out;
}
// True when every value fits its byte (LabelFusion keeps them so).
inline bool storable_evidence(const ClassEvidence& e) {
  for (std::int16_t v : e) {
    if (v < -kMaxEvidence || v > kMaxEvidence) return false;
  }
  return true;
}

// True when every class's evidence is zero: such a voxel holds no row.
// Class by class: the integrator's update tests evidence it has just
// written class by class, and a wider load of values written by narrower
// stores waits for them to reach the cache instead of taking them from
// the store buffer.
inline bool no_evidence(const ClassEvidence& e) {
  int any = 0;
  for (const std::int16_t v : e) any |= v;
  return any == 0;
}

class SemanticBlock {
 public:
  static constexpr std::size_t kMaskWords = kBlockVoxels / 64;

  // Occupancy.
  bool uniform_occupancy() const { return log_odds_ == nullptr; }
  // Every voxel's log-odds while uniform_occupancy().
  std::int16_t uniform_log_odds() const { return uniform_; }
  std::int16_t log_odds(int l) const { return log_odds_ ? log_odds_of(log_odds_[l]) : uniform_; }
  bool known(int l) const { return log_odds(l) != kUnknownLogOdds; }
  // The 512 stored log-odds (stored_log_odds()) to write into; null while
  // uniform_occupancy().
  std::int8_t* log_odds_slab() { return log_odds_; }
  const std::int8_t* log_odds_slab() const { return log_odds_; }

  // Class evidence.
  bool holds_evidence(int l) const { return (has_evidence_[l >> 6] >> (l & 63)) & 1u; }
  // Zeros for a voxel without a row.
  ClassEvidence evidence(int l) const { return holds_evidence(l) ? evidence_of(rows_[row_of(l)]) : ClassEvidence{}; }
  SemanticVoxel voxel(int l) const { return {log_odds(l), evidence(l)}; }
  std::size_t row_count() const { return row_count_; }
  std::size_t row_capacity() const { return row_capacity_; }
  const std::array<std::uint64_t, kMaskWords>& evidence_mask() const { return has_evidence_; }

  // Sets voxel l's evidence: a row updated, added (there must be room:
  // row_count() < row_capacity()) or, for all-zero evidence, removed. Every
  // value must be storable_evidence().
  void put_evidence(int l, const ClassEvidence& e) { put_evidence(l, row_of(l), e); }
  // Calls change(ClassEvidence&) on voxel l's evidence (zeros without a row)
  // and puts the result, finding the voxel's row once: the integrator's
  // hits and decays.
  template <class Change>
  void change_evidence(int l, Change&& change) {
    const std::size_t r = row_of(l);
    ClassEvidence e = holds_evidence(l) ? evidence_of(rows_[r]) : ClassEvidence{};
    change(e);
    put_evidence(l, r, e);
  }

  // Every voxel in local index order.
  DenseVoxels dense() const {
    DenseVoxels out;
    std::size_t r = 0;
    for (int l = 0; l < kBlockVoxels; ++l) {
      out[l].log_odds = log_odds(l);
      out[l].evidence = holds_evidence(l) ? evidence_of(rows_[r++]) : ClassEvidence{};
    }
    return out;
  }

 private:
  friend class SemanticBlocks;

  // Rows before voxel l's: one per voxel before it that holds evidence.
  std::size_t row_of(int l) const {
    std::size_t r = 0;
    for (int w = 0; w < (l >> 6); ++w) r += static_cast<std::size_t>(std::popcount(has_evidence_[w]));
    return r + static_cast<std::size_t>(
                   std::popcount(has_evidence_[l >> 6] & ((std::uint64_t{1} << (l & 63)) - 1)));
  }
  // put_evidence with voxel l's row index r (row_of(l)).
  void put_evidence(int l, std::size_t r, const ClassEvidence& e) {
    if (holds_evidence(l)) {
      if (no_evidence(e)) {
        remove_row(l, r);
      } else {
        rows_[r] = stored_evidence(e);
      }
      return;
    }
    if (no_evidence(e)) return;
    std::memmove(rows_ + r + 1, rows_ + r, (row_count_ - r) * sizeof(StoredEvidence));
    rows_[r] = stored_evidence(e);
    ++row_count_;
    has_evidence_[l >> 6] |= std::uint64_t{1} << (l & 63);
  }
  void remove_row(int l, std::size_t r) {
    std::memmove(rows_ + r, rows_ + r + 1, (row_count_ - r - 1) * sizeof(StoredEvidence));
    --row_count_;
    has_evidence_[l >> 6] &= ~(std::uint64_t{1} << (l & 63));
  }

  std::int8_t* log_odds_ = nullptr;   // a slab of the occupancy pool, or null
  StoredEvidence* rows_ = nullptr;    // a chunk of the evidence pool, or null
  std::array<std::uint64_t, kMaskWords> has_evidence_{};
  std::uint16_t row_count_ = 0;
  std::uint16_t row_capacity_ = 0;
  std::int16_t uniform_ = kUnknownLogOdds;
};

}  // namespace sarmap::metric
