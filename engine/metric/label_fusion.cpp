#include "engine/metric/label_fusion.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::metric {

LabelFusion::LabelFusion(const LabelFusionSettings& s) : settings_(s) {
  if (!(s.label_confidence > 1.0 / kClassCount && s.label_confidence < 1.0)) {
    throw Error(ErrorCode::InvalidArgument,
                "label fusion: label_confidence must be in (1/6, 1), got " + std::to_string(s.label_confidence));
  }
  if (!(s.evidence_clamp > 0.0 && s.evidence_clamp <= kMaxEvidenceClamp)) {
    throw Error(ErrorCode::InvalidArgument, "label fusion: evidence_clamp must be in (0, 21] nats (the map stores "
                                            "evidence in one byte per class), got " +
                                                std::to_string(s.evidence_clamp));
  }
  if (!(s.free_evidence_keep >= 0.0 && s.free_evidence_keep < 1.0)) {
    throw Error(ErrorCode::InvalidArgument, "label fusion: free_evidence_keep must be in [0, 1), got " +
                                                std::to_string(s.free_evidence_keep));
  }
  clamp_ = static_cast<int>(std::lround(s.evidence_clamp * kEvidenceScale));
  keep_q8_ = static_cast<int>(std::lround(s.free_evidence_keep * 256.0));
  const double rest = (1.0 - s.label_confidence) / (kClassCount - 1);
  for (std::size_t l = 0; l < kClassCount; ++l) {
    const double log_pivot = std::log(l == 0 ? s.label_confidence : rest);
    for (std::size_t c = 1; c < kClassCount; ++c) {
      const double log_p = std::log(c == l ? s.label_confidence : rest);
      unanimous_[l][c] = static_cast<int>(std::lround((log_p - log_pivot) * kEvidenceScale));
    }
  }
}

void LabelFusion::observe_mixed(ClassEvidence& evidence, const ClassObservation& obs, std::uint32_t classified) const {
  // A point labelled unknown says nothing about the voxel's class (a block
  // too sparse to classify, or one the map-level classifier has not reached
  // yet): only the others count (classified).
  if (settings_.fusion == ClassFusion::Histogram) {
    // The new counts saturate too: a close voxel can take more points in
    // one scan than a byte holds.
    std::array<int, kClassCount> sums{};
    for (std::size_t c = 1; c < kClassCount; ++c) sums[c] = evidence[c] + int{obs.counts[c]};
    saturate_counts(sums);
    for (std::size_t c = 1; c < kClassCount; ++c) evidence[c] = static_cast<std::int16_t>(sums[c]);
    return;
  }
  // Bayesian: p(c | z) from the mean of the points' distributions; each class
  // gains log p(c|z) - log p(pivot|z), the pivot being class 0 (observe()
  // has taken the voxels whose classified points all have one label).
  std::array<double, kClassCount> p{};
  const double n = classified;
  if (obs.has_scores) {
    double total = 0;
    for (std::size_t c = 0; c < kClassCount; ++c) {
      p[c] = std::max(static_cast<double>(obs.score_sums[c]) / n, 1e-4);
      total += p[c];
    }
    for (auto& v : p) v /= total;
  } else {
    const double conf = settings_.label_confidence;
    const double rest = (1.0 - conf) / (kClassCount - 1);
    for (std::size_t c = 0; c < kClassCount; ++c) {
      const double count = c == 0 ? 0.0 : obs.counts[c];
      p[c] = (count * conf + (n - count) * rest) / n;
    }
  }
  const double log_pivot = std::log(p[0]);
  std::array<double, kClassCount> exact{};
  std::array<long, kClassCount> rounded{};
  for (std::size_t c = 1; c < kClassCount; ++c) {
    exact[c] = evidence[c] + (std::log(p[c]) - log_pivot) * kEvidenceScale;
    rounded[c] = std::clamp<long>(std::lround(exact[c]), -clamp_, clamp_);
  }
  // Units of 1/6 nat can round two close classes to a tie, which dominant()
  // would break by class id: the class the exact sums put first stays first
  // (class 0, the pivot, wins its ties already).
  const auto best = static_cast<std::size_t>(std::max_element(exact.begin(), exact.end()) - exact.begin());
  for (std::size_t c = 0; c < kClassCount && best != 0; ++c) {
    if (c == best || rounded[c] != rounded[best] || exact[c] == exact[best]) continue;
    if (rounded[best] < clamp_) {
      ++rounded[best];
    } else {
      --rounded[c];
    }
  }
  for (std::size_t c = 1; c < kClassCount; ++c) evidence[c] = static_cast<std::int16_t>(rounded[c]);
}

ClassId LabelFusion::dominant(const ClassEvidence& evidence) {
  std::size_t best = 0;
  for (std::size_t c = 1; c < kClassCount; ++c) {
    if (evidence[c] > evidence[best]) best = c;
  }
  return static_cast<ClassId>(best);
}

}  // namespace sarmap::metric
