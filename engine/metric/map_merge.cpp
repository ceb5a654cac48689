#include "engine/metric/map_merge.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "engine/core/error.hpp"

namespace sarmap::metric {

namespace {

// Throws unless the two maps give their numbers the same meaning.
void check_same_settings(const MetricMapSettings& a, const MetricMapSettings& b) {
  const auto differ = [](const char* name, double x, double y) {
    if (x == y) return;
    throw Error(ErrorCode::InvalidArgument, std::string("cannot merge metric maps with different ") + name + ": " +
                                                std::to_string(x) + " and " + std::to_string(y));
  };
  differ("resolution", a.resolution, b.resolution);
  differ("occupancy prob_hit", a.occupancy.prob_hit, b.occupancy.prob_hit);
  differ("occupancy prob_miss", a.occupancy.prob_miss, b.occupancy.prob_miss);
  differ("occupancy clamp_min", a.occupancy.clamp_min, b.occupancy.clamp_min);
  differ("occupancy clamp_max", a.occupancy.clamp_max, b.occupancy.clamp_max);
  differ("occupancy occupied_threshold", a.occupancy.occupied_threshold, b.occupancy.occupied_threshold);
  if (a.fusion.fusion != b.fusion.fusion) {
    throw Error(ErrorCode::InvalidArgument, std::string("cannot merge metric maps with different class fusion: ") +
                                                std::string(to_string(a.fusion.fusion)) + " and " +
                                                std::string(to_string(b.fusion.fusion)));
  }
  differ("fusion label_confidence", a.fusion.label_confidence, b.fusion.label_confidence);
  differ("fusion evidence_clamp", a.fusion.evidence_clamp, b.fusion.evidence_clamp);
  differ("fusion free_evidence_keep", a.fusion.free_evidence_keep, b.fusion.free_evidence_keep);
}

ClassEvidence merge_evidence(const ClassEvidence& a, const ClassEvidence& b, const LabelFusion& fusion) {
  ClassEvidence out{};
  if (fusion.settings().fusion == ClassFusion::Bayesian) {
    // Log-odds against class 0 (which stays 0), clamped as observe() does.
    const int clamp = fusion.evidence_clamp_units();
    for (std::size_t c = 0; c < kClassCount; ++c) {
      out[c] = static_cast<std::int16_t>(std::clamp(int{a[c]} + int{b[c]}, -clamp, clamp));
    }
    return out;
  }
  // Histogram: point counts add and saturate as one map's do.
  std::array<int, kClassCount> sum{};
  for (std::size_t c = 0; c < kClassCount; ++c) sum[c] = int{a[c]} + int{b[c]};
  saturate_counts(sum);
  for (std::size_t c = 0; c < kClassCount; ++c) out[c] = static_cast<std::int16_t>(sum[c]);
  return out;
}

}  // namespace

SemanticVoxel merge_voxels(const SemanticVoxel& a, const SemanticVoxel& b, const OccupancyModel& occupancy,
                           const LabelFusion& fusion) {
  if (b.log_odds == kUnknownLogOdds && no_evidence(b.evidence)) return a;
  if (a.log_odds == kUnknownLogOdds && no_evidence(a.evidence)) return b;
  SemanticVoxel out;
  if (a.log_odds == kUnknownLogOdds || b.log_odds == kUnknownLogOdds) {
    out.log_odds = a.log_odds == kUnknownLogOdds ? b.log_odds : a.log_odds;
  } else {
    out.log_odds = static_cast<std::int16_t>(
        std::clamp(int{a.log_odds} + int{b.log_odds}, int{occupancy.min()}, int{occupancy.max()}));
  }
  out.evidence = merge_evidence(a.evidence, b.evidence, fusion);
  return out;
}

void check_mergeable(const MetricMap& into, const MetricMap& other) {
  check_same_settings(into.settings(), other.settings());
}

MergeCounts merge_into(MetricMap& into, const MetricMap& other) {
  check_mergeable(into, other);
  MergeCounts counts;
  // In key order, so that storage grows the same way whatever the hash order.
  for (const BlockKey& key : other.blocks().sorted_block_keys()) {
    const SemanticBlock& theirs = *other.blocks().find(key);
    const SemanticBlock* ours = into.blocks().find(key);
    if (ours == nullptr) {
      into.blocks().assign(key, theirs.dense());
      ++counts.blocks_added;
      continue;
    }
    ++counts.blocks_merged;
    DenseVoxels merged = ours->dense();
    const DenseVoxels added = theirs.dense();
    for (int l = 0; l < kBlockVoxels; ++l) {
      if (merged[l].log_odds != kUnknownLogOdds && added[l].log_odds != kUnknownLogOdds) ++counts.voxels_in_both;
      merged[l] = merge_voxels(merged[l], added[l], into.occupancy(), into.fusion());
    }
    into.blocks().assign(key, merged);
  }
  return counts;
}

}  // namespace sarmap::metric
