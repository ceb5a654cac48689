// Regression test of the shipped ramp model: run through the C++ engine on
// fixed scans of a held-out arena (random arena 9001, a seed never used in
// training), the network alone must keep the per-point accuracy recorded
// when it was trained, and beat the geometric baseline on the same scans; on
// a held-out arena with a steeply pitched camera (9005), the steep-surface
// veto must keep the gain it was measured to bring; on 9003, relabelling
// ramp side faces (tests/semantic/ramp_side_faces_test.cpp) must keep its
// gain on inclined ramps, and on 9005's first frames the wall bands rule
// (tests/semantic/wall_bands_test.cpp) its gain on walls; and the shipped
// configuration on the map must keep its figures on a test-split arena seen
// by both sensors. The figures were
// measured with this test's own code (see PERF.md, "Classifiers"); the
// thresholds sit a small margin below.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "engine/core/classes.hpp"
#include "engine/eval/point_evaluation.hpp"
#include "engine/pipeline/mapper.hpp"
#include "engine/pipeline/point_classifier.hpp"
#include "engine/sim/random_arena.hpp"
#include "engine/sim/simulator.hpp"
#include "tests/release_only.hpp"

namespace sarmap {
namespace {

constexpr std::uint64_t kHeldOutArena = 9001;
constexpr std::uint64_t kSteepPitchArena = 9005;  // camera pitched -24.3 degrees
constexpr std::uint64_t kRampSideArena = 9003;    // ramps seen side-on
constexpr std::size_t kScans = 6;  // spread evenly along the trajectory

// The cases below that test one rule at a time run the blocks without
// overlap (the shipped model's block size), as when their figures were
// recorded; the last case runs the shipped configuration as it is.
constexpr double kNoOverlapStride = 1.5;

// Recorded when the model was committed (again on 2026-11-28 for the model
// fine-tuned on map-level blocks of both sensors, which classified single
// scans less well than its predecessor: 0.9203 mean against 0.9572, and on
// 2026-12-01 for the model fine-tuned on varied sensor mountings, and on
// 2026-12-02 for the one fine-tuned at 1,024 points per block: 0.9564 ->
// 0.9544 mean here, the veto's and the side faces' scans lower); margins
// absorb nothing but future changes of sampling order, so they are small.
constexpr double kRecordedMeanIou = 0.9544;
constexpr double kRecordedInclinedIou = 0.8841;
constexpr double kRecordedFlatIou = 0.9746;
// Arena 9005 with the steep-surface veto, and its gain in mean IoU over the
// network alone on the same scans.
constexpr double kRecordedVetoWallIou = 0.7646;
constexpr double kRecordedVetoInclinedIou = 0.7779;
constexpr double kRecordedVetoGain = 0.1806;  // 0.6446 -> 0.8252
// Arena 9003 (veto on) with the ramp side faces relabelled, and their gain
// in inclined-ramp IoU over the same run without.
constexpr double kRecordedSidesInclinedIou = 0.8508;
constexpr double kRecordedSidesInclinedGain = 0.0499;  // 0.8009 -> 0.8508
// Arena 9005's first frames (the robot faces a long wall, only its lowest
// band in view, which the network calls other) with the wall bands rule,
// and its gain in wall IoU over the same frames without.
const std::vector<std::size_t> kFirstFrames{0, 4, 8};
constexpr double kRecordedBandsWallIou = 0.9055;
constexpr double kRecordedBandsWallGain = 0.5959;  // 0.3096 -> 0.9055
// The held-out arena's scans with every rule, and the gains of wall feet
// over the same scans without it (small: a few floor points per scan).
constexpr double kRecordedFeetTerrainIou = 0.9857;
constexpr double kRecordedFeetWallIou = 0.9805;
constexpr double kRecordedFeetTerrainGain = 0.0034;  // 0.9823 -> 0.9857
constexpr double kRecordedFeetWallGain = 0.0038;     // 0.9767 -> 0.9805
// The shipped configuration (the accumulated map classified, blocks
// overlapping by a quarter, every rule on) on the held-out arena's scans;
// the model before 2026-11-28 scored mean IoU 0.9695, inclined ramp 0.9240,
// flat ramp 0.9779 here, the one of 2026-11-28 0.9653, 0.9021 and 0.9821,
// the one of 2026-12-01 0.9731, 0.9285 and 0.9860.
constexpr double kRecordedDefaultMeanIou = 0.9672;
constexpr double kRecordedDefaultInclinedIou = 0.9124;
constexpr double kRecordedDefaultFlatIou = 0.9838;
constexpr double kMargin = 0.02;

// The given frames of a held-out arena, classified in order by one classifier.
eval::ConfusionMatrix classify_frames(const pipeline::ClassifierConfig& config, std::uint64_t arena_seed,
                                      const std::vector<std::size_t>& frames) {
  sim::SimulationOptions options;
  options.seed = 7;
  const sim::Simulator simulator(sim::random_arena(arena_seed), options);
  const auto classifier = pipeline::make_point_classifier(config);
  eval::ConfusionMatrix confusion;
  for (const std::size_t frame : frames) {
    Scan scan = simulator.simulate(frame);
    PointBuffer& points = scan.points;
    points.enable_gt_labels();
    // The simulator's truth, kept beside the prediction the classifier writes.
    std::copy(points.labels().begin(), points.labels().end(), points.gt_labels().begin());
    classifier->classify(points);
    confusion.merge(eval::evaluate_points(points, "frame " + std::to_string(frame)).confusion);
  }
  return confusion;
}

// kScans frames spread evenly along the trajectory.
eval::ConfusionMatrix classify_held_out_scans(const pipeline::ClassifierConfig& config,
                                              std::uint64_t arena_seed = kHeldOutArena) {
  sim::SimulationOptions options;
  options.seed = 7;
  const sim::Simulator simulator(sim::random_arena(arena_seed), options);
  std::vector<std::size_t> frames;
  for (std::size_t i = 0; i < kScans; ++i) frames.push_back((2 * i + 1) * simulator.frame_count() / (2 * kScans));
  return classify_frames(config, arena_seed, frames);
}

void print_figures(const char* name, const eval::ConfusionMatrix& c) {
  std::printf("%s: accuracy %.4f, mean IoU %.4f, terrain %.4f, wall %.4f, inclined %.4f, flat %.4f\n", name,
              c.accuracy().value_or(0), c.mean_iou().value_or(0), c.iou(ClassId::Terrain).value_or(0),
              c.iou(ClassId::Wall).value_or(0), c.iou(ClassId::InclinedRamp).value_or(0),
              c.iou(ClassId::FlatRamp).value_or(0));
}

pipeline::ClassifierConfig shipped_model(bool ramp_veto, bool ramp_sides = false, bool wall_bands = false,
                                         bool wall_feet = false) {
  pipeline::ClassifierConfig dgcnn;
  dgcnn.model = std::filesystem::path(SARMAP_SOURCE_DIR) / "datasets" / "models" / "ramps-dgcnn.safetensors";
  dgcnn.per_scan = true;  // the rules' figures were recorded on scans classified one by one
  dgcnn.dgcnn.stride = kNoOverlapStride;
  dgcnn.rules.ramp_veto.enabled = ramp_veto;
  dgcnn.rules.ramp_sides.enabled = ramp_sides;
  dgcnn.rules.wall_bands.enabled = wall_bands;
  dgcnn.rules.wall_feet.enabled = wall_feet;
  return dgcnn;
}

TEST(ShippedModel, KeepsItsRecordedAccuracyOnAHeldOutArena) {
  RELEASE_ONLY();
  const pipeline::ClassifierConfig dgcnn = shipped_model(false);
  const eval::ConfusionMatrix net = classify_held_out_scans(dgcnn);
  pipeline::ClassifierConfig geometric;
  geometric.kind = pipeline::ClassifierKind::Geometric;
  const eval::ConfusionMatrix baseline = classify_held_out_scans(geometric);
  print_figures("dgcnn", net);
  print_figures("geometric", baseline);

  ASSERT_GT(net.total(), 100'000u);
  EXPECT_GE(net.mean_iou().value(), kRecordedMeanIou - kMargin);
  EXPECT_GE(net.iou(ClassId::InclinedRamp).value(), kRecordedInclinedIou - kMargin);
  EXPECT_GE(net.iou(ClassId::FlatRamp).value(), kRecordedFlatIou - kMargin);
  EXPECT_GT(net.mean_iou().value(), baseline.mean_iou().value());
}

TEST(ShippedModel, SteepSurfaceVetoKeepsFarWallBandsWallsUnderASteepCamera) {
  RELEASE_ONLY();
  const eval::ConfusionMatrix net = classify_held_out_scans(shipped_model(false), kSteepPitchArena);
  const eval::ConfusionMatrix vetoed = classify_held_out_scans(shipped_model(true), kSteepPitchArena);
  print_figures("dgcnn", net);
  print_figures("dgcnn + veto", vetoed);
  EXPECT_GE(vetoed.iou(ClassId::Wall).value(), kRecordedVetoWallIou - kMargin);
  EXPECT_GE(vetoed.iou(ClassId::InclinedRamp).value(), kRecordedVetoInclinedIou - kMargin);
  EXPECT_GT(vetoed.mean_iou().value(), net.mean_iou().value() + kRecordedVetoGain - kMargin);
}

TEST(ShippedModel, RampSideFacesTurnWallLabelsUnderRampDecksIntoRamp) {
  RELEASE_ONLY();
  const eval::ConfusionMatrix vetoed = classify_held_out_scans(shipped_model(true), kRampSideArena);
  const eval::ConfusionMatrix sides = classify_held_out_scans(shipped_model(true, true), kRampSideArena);
  print_figures("dgcnn + veto", vetoed);
  print_figures("dgcnn + veto + sides", sides);
  EXPECT_GE(sides.iou(ClassId::InclinedRamp).value(), kRecordedSidesInclinedIou - kMargin);
  EXPECT_GT(sides.iou(ClassId::InclinedRamp).value(),
            vetoed.iou(ClassId::InclinedRamp).value() + kRecordedSidesInclinedGain - kMargin);
  EXPECT_GE(sides.iou(ClassId::Wall).value(), vetoed.iou(ClassId::Wall).value());  // walls lose nothing
}

TEST(ShippedModel, WallBandsTurnALongWallTheNetworkCalledOtherIntoWall) {
  RELEASE_ONLY();
  const eval::ConfusionMatrix before = classify_frames(shipped_model(true, true), kSteepPitchArena, kFirstFrames);
  const eval::ConfusionMatrix after = classify_frames(shipped_model(true, true, true), kSteepPitchArena, kFirstFrames);
  print_figures("dgcnn + veto + sides", before);
  print_figures("dgcnn + veto + sides + bands", after);
  EXPECT_GE(after.iou(ClassId::Wall).value(), kRecordedBandsWallIou - kMargin);
  EXPECT_GT(after.iou(ClassId::Wall).value(), before.iou(ClassId::Wall).value() + kRecordedBandsWallGain - kMargin);
  // Nothing else moves: the rule only turns other into wall.
  EXPECT_DOUBLE_EQ(after.iou(ClassId::InclinedRamp).value(), before.iou(ClassId::InclinedRamp).value());
}

TEST(ShippedModel, WallFeetTurnFloorLabelledWallIntoTerrain) {
  RELEASE_ONLY();
  const eval::ConfusionMatrix before = classify_held_out_scans(shipped_model(true, true, true));
  const eval::ConfusionMatrix after = classify_held_out_scans(shipped_model(true, true, true, true));
  print_figures("dgcnn + veto + sides + bands", before);
  print_figures("dgcnn + veto + sides + bands + feet", after);
  EXPECT_GE(after.iou(ClassId::Terrain).value(), kRecordedFeetTerrainIou - kMargin);
  EXPECT_GE(after.iou(ClassId::Wall).value(), kRecordedFeetWallIou - kMargin);
  // At least half the recorded gains (a margin as wide as the others would exceed them).
  EXPECT_GT(after.iou(ClassId::Terrain).value(), before.iou(ClassId::Terrain).value() + kRecordedFeetTerrainGain / 2);
  EXPECT_GT(after.iou(ClassId::Wall).value(), before.iou(ClassId::Wall).value() + kRecordedFeetWallGain / 2);
  // Nothing else moves: the rule only turns wall into terrain.
  EXPECT_DOUBLE_EQ(after.iou(ClassId::InclinedRamp).value(), before.iou(ClassId::InclinedRamp).value());
}

TEST(ShippedModel, TheShippedConfigurationKeepsItsRecordedAccuracy) {
  RELEASE_ONLY();
  pipeline::ClassifierConfig shipped;  // what `sarmap run` uses by default
  shipped.model = std::filesystem::path(SARMAP_SOURCE_DIR) / "datasets" / "models" / "ramps-dgcnn.safetensors";
  const eval::ConfusionMatrix c = classify_held_out_scans(shipped);
  print_figures("dgcnn, shipped configuration", c);
  EXPECT_GE(c.mean_iou().value(), kRecordedDefaultMeanIou - kMargin);
  EXPECT_GE(c.iou(ClassId::InclinedRamp).value(), kRecordedDefaultInclinedIou - kMargin);
  EXPECT_GE(c.iou(ClassId::FlatRamp).value(), kRecordedDefaultFlatIou - kMargin);
}

// The test split (PERF.md, "Classifiers": arenas 9101-9105, never used to
// decide anything): the shipped configuration end to end, a Mapper over
// every kTestEvery-th frame of test arena 9101 seen by the depth camera and
// by the 16-ring LiDAR, its kept points taking the map's final classes and
// the rules as `semantic_points.ply` does, scored against the simulator's
// labels. Recorded with this code on 2026-11-28 (machine A), again when
// blocks classified before waited for 512 new points (depth 0.9596 -> 0.9588,
// LiDAR 0.9019 -> 0.8984 mean IoU) and for the model fine-tuned on map-level
// blocks of both sensors (depth 0.9637, LiDAR 0.9210) and on 2026-12-01 for
// the model fine-tuned on varied mountings (machine D; depth 0.9627, LiDAR
// 0.9219) and on 2026-12-02 for the one at 1,024 points per block (D); the
// whole test split's figures are in PERF.md.
constexpr std::uint64_t kTestArena = 9101;
constexpr std::size_t kTestEvery = 8;
constexpr double kRecordedTestDepthMeanIou = 0.9498;
constexpr double kRecordedTestDepthInclinedIou = 0.9334;
constexpr double kRecordedTestDepthFlatIou = 0.8938;
constexpr double kRecordedTestLidarMeanIou = 0.9285;
constexpr double kRecordedTestLidarInclinedIou = 0.9255;
constexpr double kRecordedTestLidarFlatIou = 0.8327;

eval::ConfusionMatrix map_test_arena(SensorType sensor) {
  sim::RandomSensor seen_by;
  seen_by.type = sensor;
  sim::SimulationOptions options;
  options.seed = 7;  // as tools/python/eval_classifiers.py simulates
  const sim::Simulator simulator(sim::random_arena(kTestArena, seen_by), options);
  pipeline::MapperConfig config;  // what `sarmap run` uses by default
  config.classifier.model = std::filesystem::path(SARMAP_SOURCE_DIR) / "datasets" / "models" / "ramps-dgcnn.safetensors";
  pipeline::Mapper mapper(config);
  for (std::size_t frame = 0; frame < simulator.frame_count(); frame += kTestEvery) {
    Scan scan = simulator.simulate(frame);
    mapper.integrate(scan);
  }
  mapper.finish();
  PointBuffer kept = mapper.semantic_points();
  mapper.classifier().relabel(kept);
  return eval::evaluate_points(kept, "test arena").confusion;
}

TEST(ShippedModel, KeepsItsTestSplitFiguresOnTheMapWithBothSensors) {
  RELEASE_ONLY();
  const eval::ConfusionMatrix depth = map_test_arena(SensorType::DepthCamera);
  const eval::ConfusionMatrix lidar = map_test_arena(SensorType::Lidar);
  print_figures("test arena, depth camera", depth);
  print_figures("test arena, LiDAR", lidar);
  ASSERT_GT(depth.total(), 10'000u);
  ASSERT_GT(lidar.total(), 10'000u);
  EXPECT_GE(depth.mean_iou().value(), kRecordedTestDepthMeanIou - kMargin);
  EXPECT_GE(depth.iou(ClassId::InclinedRamp).value(), kRecordedTestDepthInclinedIou - kMargin);
  EXPECT_GE(depth.iou(ClassId::FlatRamp).value(), kRecordedTestDepthFlatIou - kMargin);
  EXPECT_GE(lidar.mean_iou().value(), kRecordedTestLidarMeanIou - kMargin);
  EXPECT_GE(lidar.iou(ClassId::InclinedRamp).value(), kRecordedTestLidarInclinedIou - kMargin);
  EXPECT_GE(lidar.iou(ClassId::FlatRamp).value(), kRecordedTestLidarFlatIou - kMargin);
}

}  // namespace
}  // namespace sarmap
