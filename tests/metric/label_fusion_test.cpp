// Class fusion: histogram counts, Bayesian log-odds against the pivot class,
// saturation, decay of freed voxels, and settings validation.
#include "engine/metric/label_fusion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "engine/core/error.hpp"

namespace sarmap::metric {
namespace {

ClassObservation hard(ClassId id, std::uint16_t n) {
  ClassObservation o;
  o.counts[static_cast<int>(id)] = n;
  o.points = n;
  return o;
}

TEST(LabelFusion, HistogramCountsAndSaturatesByHalving) {
  LabelFusionSettings s;
  s.fusion = ClassFusion::Histogram;
  const LabelFusion f(s);
  ClassEvidence e{};
  f.observe(e, hard(ClassId::Wall, 3));
  f.observe(e, hard(ClassId::Terrain, 2));
  EXPECT_EQ(e[2], 3);
  EXPECT_EQ(e[1], 2);
  EXPECT_EQ(LabelFusion::dominant(e), ClassId::Wall);
  // Past a byte's kMaxEvidence every class halves, the new counts included.
  e[2] = 120;
  e[1] = 40;
  f.observe(e, hard(ClassId::Wall, 10));
  EXPECT_EQ(e[2], 65);
  EXPECT_EQ(e[1], 20);
  // One scan can put more points in a voxel than a byte holds: they halve too.
  ClassEvidence close{};
  ClassObservation many = hard(ClassId::Wall, 600);
  many.add(hard(ClassId::Terrain, 300));
  f.observe(close, many);
  EXPECT_EQ(close[2], 75);
  EXPECT_EQ(close[1], 37);
  close = {};
  f.observe(close, hard(ClassId::InclinedRamp, 65535));
  EXPECT_EQ(close[3], 127);
}

TEST(LabelFusion, BayesianAddsLogRatioAgainstThePivot) {
  const LabelFusion f;  // Bayesian, confidence 0.9
  ClassEvidence e{};
  f.observe(e, hard(ClassId::InclinedRamp, 1));
  const double expected = std::log(0.9 / 0.02) * kEvidenceScale;
  EXPECT_NEAR(e[3], expected, 1.0);
  EXPECT_EQ(e[0], 0);
  EXPECT_EQ(e[1], 0);
  EXPECT_EQ(LabelFusion::dominant(e), ClassId::InclinedRamp);
  // Two later observations of flat ramp outweigh one of inclined ramp.
  f.observe(e, hard(ClassId::FlatRamp, 1));
  f.observe(e, hard(ClassId::FlatRamp, 1));
  EXPECT_EQ(LabelFusion::dominant(e), ClassId::FlatRamp);
  // Evidence is clamped, so a voxel can still change its mind.
  for (int i = 0; i < 100; ++i) f.observe(e, hard(ClassId::FlatRamp, 1));
  EXPECT_EQ(e[4], static_cast<int>(20.0 * kEvidenceScale));
}

TEST(LabelFusion, BayesianUsesScoresWhenGiven) {
  const LabelFusion f;
  ClassObservation o;
  o.points = 2;
  o.has_scores = true;
  o.score_sums = {0.2f, 1.2f, 0.2f, 0.2f, 0.1f, 0.1f};  // mean: terrain 0.6, unknown 0.1
  ClassEvidence e{};
  f.observe(e, o);
  EXPECT_NEAR(e[1], std::log(0.6 / 0.1) * kEvidenceScale, 1.0);
  EXPECT_NEAR(e[4], std::log(0.05 / 0.1) * kEvidenceScale, 1.0);
}

// Evidence in 1/6 nat rounds close classes alike; the class the scores put
// first must still come out first (the map-level classifier's voxel classes
// are one such observation each).
TEST(LabelFusion, BayesianRoundingKeepsTheClassTheScoresPutFirst) {
  const LabelFusion f;
  ClassObservation close;
  close.points = 1;
  close.has_scores = true;
  close.score_sums = {0.05f, 0.05f, 0.400f, 0.401f, 0.05f, 0.049f};  // inclined ramp just ahead of wall
  ClassEvidence e{};
  f.observe(e, close);
  EXPECT_EQ(LabelFusion::dominant(e), ClassId::InclinedRamp) << e[2] << " " << e[3];
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> score(0.0f, 1.0f);
  int checked = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    ClassObservation o;
    o.points = 1 + trial % 4;
    o.has_scores = true;
    for (float& v : o.score_sums) v = score(rng) * static_cast<float>(o.points);
    if (trial % 2 == 0) o.score_sums[static_cast<std::size_t>(1 + trial % 5)] = o.score_sums[1 + (trial + 1) % 5] * 1.01f;
    const auto first = static_cast<std::size_t>(std::max_element(o.score_sums.begin(), o.score_sums.end()) -
                                                o.score_sums.begin());
    if (std::count(o.score_sums.begin(), o.score_sums.end(), o.score_sums[first]) > 1) continue;
    ClassEvidence from_none{};
    f.observe(from_none, o);
    ASSERT_EQ(static_cast<std::size_t>(LabelFusion::dominant(from_none)), first) << "trial " << trial;
    ++checked;
  }
  EXPECT_GT(checked, 4900);
}

TEST(LabelFusion, DecayShrinksEvidenceGradually) {
  const LabelFusion f;
  ClassEvidence e{0, 0, 100, -40, 0, 0};
  f.decay(e);
  EXPECT_EQ(e[2], 50);
  EXPECT_EQ(e[3], -20);
  for (int i = 0; i < 12; ++i) f.decay(e);
  EXPECT_EQ(e[2], 0);
  EXPECT_EQ(LabelFusion::dominant(ClassEvidence{}), ClassId::Unknown);
}

TEST(LabelFusion, RejectsBadSettings) {
  LabelFusionSettings s;
  s.label_confidence = 0.1;
  EXPECT_THROW(LabelFusion{s}, Error);
  s = {};
  s.evidence_clamp = 500;
  EXPECT_THROW(LabelFusion{s}, Error);
  s.evidence_clamp = 21.5;  // beyond what a byte holds at 1/6 nat
  EXPECT_THROW(LabelFusion{s}, Error);
  s.evidence_clamp = kMaxEvidenceClamp;
  EXPECT_EQ(LabelFusion(s).evidence_clamp_units(), 126);
  s = {};
  s.free_evidence_keep = 1.0;
  EXPECT_THROW(LabelFusion{s}, Error);
}

}  // namespace
}  // namespace sarmap::metric

namespace sarmap::metric {
namespace {

TEST(LabelFusion, UnanimousShortcutMatchesTheGeneralFormula) {
  const LabelFusion f;
  for (int l = 1; l < 6; ++l) {
    ClassEvidence fast{}, general{};
    f.observe(fast, hard(static_cast<ClassId>(l), 3));
    // Same distribution through the general path: a mixed observation whose
    // minority share is zero is not possible, so use scores equal to the hard model.
    ClassObservation o;
    o.points = 3;
    o.has_scores = true;
    for (int c = 0; c < 6; ++c) o.score_sums[c] = 3.0f * (c == l ? 0.9f : 0.02f);
    f.observe(general, o);
    for (int c = 0; c < 6; ++c) EXPECT_NEAR(fast[c], general[c], 1) << l << " " << c;
  }
}

// Unknown labels come from blocks too sparse to classify or not classified
// yet: they must neither pull a voxel towards no class nor dilute the others.
TEST(LabelFusion, PointsLabelledUnknownSayNothing) {
  for (const ClassFusion fusion : {ClassFusion::Bayesian, ClassFusion::Histogram}) {
    LabelFusionSettings s;
    s.fusion = fusion;
    const LabelFusion f(s);
    ClassEvidence evidence{};
    f.observe(evidence, hard(ClassId::Wall, 2));
    const ClassEvidence before = evidence;
    f.observe(evidence, hard(ClassId::Unknown, 7));
    EXPECT_EQ(evidence, before) << to_string(fusion);
    // Mixed: 2 ramp and 1 wall points among 5 unknown ones count as 2 ramp and 1 wall.
    ClassObservation mixed = hard(ClassId::Unknown, 5), plain = hard(ClassId::InclinedRamp, 2);
    plain.add(hard(ClassId::Wall, 1));
    mixed.add(plain);
    ClassEvidence with_unknown = before, without = before;
    f.observe(with_unknown, mixed);
    f.observe(without, plain);
    EXPECT_EQ(with_unknown, without) << to_string(fusion);
    EXPECT_NE(without, before);
  }
}

}  // namespace
}  // namespace sarmap::metric
