// Fusing per-point class labels into per-voxel class evidence: paper 000's
// histogram (count points per class, dominant class wins) or a multi-class
// recursive Bayesian update in log-odds space (paper 003), selectable.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <string_view>

#include "engine/core/classes.hpp"

namespace sarmap::metric {

enum class ClassFusion : std::uint8_t { Histogram = 0, Bayesian = 1 };

// "histogram" or "bayesian", as manifest.json and `sarmap info` name them.
constexpr std::string_view to_string(ClassFusion fusion) {
  return fusion == ClassFusion::Bayesian ? "bayesian" : "histogram";
}

// Every evidence value stays within +-kMaxEvidence, so that the map stores
// each in one byte (semantic_block.hpp): histogram counts saturate there
// (by halving every class) and Bayesian evidence, fixed point at 1 unit =
// 1/6 nat, is clamped within it (evidence_clamp <= 21 nats).
inline constexpr int kMaxEvidence = 127;
inline constexpr double kEvidenceScale = 6.0;
inline constexpr double kMaxEvidenceClamp = 21.0;

struct LabelFusionSettings {
  ClassFusion fusion = ClassFusion::Bayesian;
  // p(label | z) assumed for a hard label; the rest is spread evenly over the other classes.
  double label_confidence = 0.9;
  // Bayesian evidence stays within +-this many nats, so a voxel can still change class.
  double evidence_clamp = 20.0;
  // Fraction of its class evidence a free voxel keeps per miss: free voxels
  // carry no class, but one that turns free loses it gradually.
  double free_evidence_keep = 0.5;
};

using ClassEvidence = std::array<std::int16_t, kClassCount>;

// Histogram counts past kMaxEvidence: every class halves until the largest
// fits, which keeps their ratios (an observation, a merge, an old file).
inline void saturate_counts(std::array<int, kClassCount>& counts) {
  int most = 0;
  for (const int n : counts) most = std::max(most, n);
  for (; most > kMaxEvidence; most /= 2) {
    for (int& n : counts) n /= 2;
  }
}

// What the points that fell in one voxel during one scan said about its class.
struct ClassObservation {
  std::array<std::uint16_t, kClassCount> counts{};  // points per hard label (saturating)
  std::array<float, kClassCount> score_sums{};      // sums of per-class probabilities
  bool has_scores = false;
  std::uint32_t points = 0;

  // Folds in the observations of more points of the same voxel.
  void add(const ClassObservation& more) {
    for (std::size_t c = 0; c < kClassCount; ++c) {
      const unsigned sum = static_cast<unsigned>(counts[c]) + more.counts[c];
      counts[c] = static_cast<std::uint16_t>(sum < 0xffffu ? sum : 0xffffu);
      score_sums[c] += more.score_sums[c];
    }
    has_scores = has_scores || more.has_scores;
    points += more.points;
  }
};

class LabelFusion {
 public:
  // Throws sarmap::Error (InvalidArgument) for a confidence outside (1/6, 1),
  // an evidence clamp outside (0, kMaxEvidenceClamp] or a keep fraction
  // outside [0, 1).
  explicit LabelFusion(const LabelFusionSettings& settings = {});

  const LabelFusionSettings& settings() const { return settings_; }
  // One update per voxel per scan, with everything its points said; points
  // labelled unknown say nothing, and a voxel that only they hit keeps its
  // evidence.
  // Inline where every classified point has one label (without scores),
  // the common case: the integrator calls it for every hit voxel.
  void observe(ClassEvidence& evidence, const ClassObservation& observation) const {
    const std::uint32_t classified = classified_points(observation);
    if (classified == 0) return;
    if (settings_.fusion == ClassFusion::Bayesian && !observation.has_scores) {
      for (std::size_t l = 1; l < kClassCount; ++l) {
        if (observation.counts[l] != classified) continue;
        for (std::size_t c = 1; c < kClassCount; ++c) {
          evidence[c] = static_cast<std::int16_t>(std::clamp(evidence[c] + unanimous_[l][c], -clamp_, clamp_));
        }
        return;
      }
    }
    observe_mixed(evidence, observation, classified);
  }
  // A miss that leaves the voxel free: evidence shrinks towards none.
  // Inline: called for every free voxel of every scan.
  void decay(ClassEvidence& evidence) const {
    for (auto& e : evidence) e = static_cast<std::int16_t>(e * keep_q8_ / 256);
  }
  // The class with the most evidence (lowest id on ties); Unknown when none has any.
  static ClassId dominant(const ClassEvidence& evidence);
  // Bayesian evidence stays within +-this, in evidence units (1/6 nat).
  int evidence_clamp_units() const { return clamp_; }

 private:
  // Points that say a class: those labelled unknown say nothing.
  static std::uint32_t classified_points(const ClassObservation& obs) {
    return obs.points - std::min<std::uint32_t>(obs.counts[0], obs.points);
  }
  // observe() for histograms, scores and voxels whose points disagree.
  void observe_mixed(ClassEvidence& evidence, const ClassObservation& observation, std::uint32_t classified) const;

  LabelFusionSettings settings_;
  int clamp_ = 0;
  int keep_q8_ = 0;
  // Bayesian deltas when every point of the voxel has label l, the common
  // case: precomputed, since six logs per hit voxel showed in profiles.
  std::array<std::array<int, kClassCount>, kClassCount> unanimous_{};
};

}  // namespace sarmap::metric
