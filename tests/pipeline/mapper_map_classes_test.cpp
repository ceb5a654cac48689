// The Mapper with the classifier of the accumulated map (the fixture model
// on a synthetic room): the metric map's voxel classes follow the labelled
// point map, also for a model whose logits map many to one onto sarmap's
// classes, finish() leaves no block with points no classification has
// seen, per-scan classification stays available, and a bounded map lets the
// labelled point map go of what it dropped.
#include "engine/pipeline/mapper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>

#include "engine/metric/voxel_key.hpp"
#include "engine/pipeline/run_summary.hpp"
#include "tests/metric/synthetic_room.hpp"
#include "tests/release_only.hpp"
#include "tests/semantic/fixture_model.hpp"

namespace sarmap::pipeline {
namespace {

MapperConfig map_classifier_config() {
  MapperConfig config;
  config.voxel = 0.1;
  config.semantic_points_voxel = 0.1;
  config.classifier.kind = ClassifierKind::Dgcnn;
  config.classifier.model = test::fixture_model_c6();
  config.classifier.per_scan = false;
  config.classifier.map_cell = 0.05;
  return config;
}

void integrate_room(Mapper& mapper, int frames) {
  testing::SyntheticRoom room;
  for (int f = 0; f < frames; ++f) {
    auto r = room.frame(f, frames, 80, 60);
    Scan scan;
    scan.points = r.points;
    scan.origin = r.origin;
    mapper.integrate(scan);
  }
}

// Reference: each voxel's class from its map points' mean scores, summed per
// class (a point its blocks have not classified borrows a classified
// neighbour's, as the map does).
std::map<std::uint64_t, ClassId> voxel_classes_of_point_map(const DgcnnMapClassifier& classifier, double voxel) {
  const LabelledPointMap& map = classifier.map();
  const std::vector<ClassId>& classes = classifier.channel_classes();
  std::map<std::uint64_t, std::vector<double>> sums;
  std::vector<float> mean(classes.size());
  for (std::uint32_t p = 0; p < map.size(); ++p) {
    const std::uint32_t scored = map.scored_point(p);
    if (scored == LabelledPointMap::kNoPoint) continue;
    map.mean_scores(scored, mean.data());
    auto& s = sums[metric::pack(metric::key_of(map.points().x()[p], map.points().y()[p], map.points().z()[p], 1.0 / voxel))];
    s.resize(classes.size());
    for (std::size_t c = 0; c < classes.size(); ++c) s[c] += mean[c];
  }
  std::map<std::uint64_t, ClassId> result;
  for (const auto& [key, s] : sums) {
    result[key] = classes[static_cast<std::size_t>(std::max_element(s.begin(), s.end()) - s.begin())];
  }
  return result;
}

TEST(MapperMapClasses, VoxelClassesFollowTheLabelledPointMapAfterFinish) {
  RELEASE_ONLY();  // minutes under the sanitizers; the bounded case below runs the same path there
  const MapperConfig config = map_classifier_config();
  Mapper mapper(config);
  integrate_room(mapper, 6);
  mapper.finish();
  const DgcnnMapClassifier* classifier = mapper.classifier().accumulated_map();
  ASSERT_NE(classifier, nullptr);
  EXPECT_TRUE(mapper.classifier().labels_arrive_late());
  EXPECT_GT(mapper.profile().counter("metric", "voxels_classed_from_point_map"), 0.0);
  const auto expected = voxel_classes_of_point_map(*classifier, config.voxel);
  std::size_t occupied = 0, agree = 0;
  for (const auto& [word, cls] : expected) {
    const metric::VoxelKey key = metric::unpack_voxel(word);
    if (mapper.metric_map().state(key) != metric::VoxelState::Occupied) continue;
    ++occupied;
    agree += mapper.metric_map().class_of(key) == cls;
  }
  ASSERT_GT(occupied, 100u);
  // Sums in float against the map's quantised evidence: ties may round apart.
  EXPECT_GE(agree, occupied * 99 / 100) << agree << " of " << occupied;
  // The last scans' blocks were still waiting, and nothing waits now.
  const double at_finish = mapper.profile().counter("classify", "blocks_at_finish");
  EXPECT_GT(at_finish, 0.0);
  // The point map's bytes after every scan (finish() not included), beside
  // the metric map's in the profile.
  const StageProfile::LevelStats point_map = mapper.profile().level("classify", "point_map_bytes");
  EXPECT_EQ(point_map.scans, mapper.profile().scan_count());
  EXPECT_GT(point_map.last, static_cast<double>(classifier->map().size() * 12));
  mapper.finish();
  EXPECT_EQ(mapper.profile().counter("classify", "blocks_at_finish"), at_finish);
  // summary.json reports the labelled point map beside the metric map.
  const nlohmann::ordered_json summary = run_summary_json(mapper);
  const auto& points = summary.at("labelled_point_map");
  EXPECT_EQ(points.at("points"), classifier->map().size());
  EXPECT_EQ(points.at("blocks"), classifier->blocks().block_count());
  EXPECT_EQ(points.at("blocks_classified"), classifier->blocks_classified());
  EXPECT_EQ(points.at("bytes"), classifier->map().memory_bytes() + classifier->blocks().memory_bytes());
  EXPECT_GT(points.at("bytes").get<std::size_t>(), classifier->map().size() * 12);
}

// The same with the 13-class S3DIS fixture, whose logits count for terrain,
// wall and other: a voxel's class is the arg-max of its points' mean scores
// summed per sarmap class, not the class of the single highest logit.
// The kept points (semantic_points.ply) take their classes from the map when
// the run is written, and then go through the same rules as the scans did,
// with the ramp decks the scans showed: the reference replays the scans'
// network labels (a Mapper with every rule off holds the same point map)
// through a chain of its own.
TEST(MapperMapClasses, KeptPointsGoThroughTheRulesAsTheScansDid) {
  RELEASE_ONLY();  // two DGCNN Mappers: minutes under the sanitizers, for plumbing RuleChain's own tests cover
  MapperConfig with_rules = map_classifier_config();
  with_rules.classifier.rules.wall_bands.min_length = 0.3;  // the fixture room's patches are short
  MapperConfig without = with_rules;
  for (std::string_view rule : kRuleNames) rule_enabled(without.classifier.rules, rule) = false;
  Mapper ruled(with_rules), plain(without);
  RuleChain replay(with_rules.classifier.rules);
  testing::SyntheticRoom room;
  RuleChanges by_scans;
  for (int f = 0; f < 6; ++f) {
    auto r = room.frame(f, 6, 80, 60);
    Scan a, b;
    a.points = b.points = r.points;
    a.origin = b.origin = r.origin;
    ruled.integrate(a);
    plain.integrate(b);
    by_scans += replay.apply(b.points);  // the network's labels of the scan, as `ruled` saw them
    ASSERT_EQ(a.points.labels().size(), b.points.labels().size());
    for (std::size_t i = 0; i < a.points.size(); ++i) ASSERT_EQ(a.points.labels()[i], b.points.labels()[i]) << f << " " << i;
  }
  ASSERT_GT(by_scans.total(), 0u) << "the fixture room gives the rules nothing to change";
  PointBuffer kept = plain.semantic_points(), expected = plain.semantic_points();
  ASSERT_GT(kept.size(), 100u);
  plain.classifier().relabel(expected);
  const RuleChanges reapplied = replay.reapply(expected);
  ruled.classifier().relabel(kept);
  for (std::size_t i = 0; i < kept.size(); ++i) ASSERT_EQ(kept.labels()[i], expected.labels()[i]) << i;
  EXPECT_GT(reapplied.total(), 0u);
}

TEST(MapperMapClasses, VoxelClassesSumTheLogitsOfEachSarmapClass) {
  MapperConfig config = map_classifier_config();
  config.classifier.model = SARMAP_TEST_DATA_DIR "/dgcnn/model_s3dis13.safetensors";
  Mapper mapper(config);
  integrate_room(mapper, 6);
  mapper.finish();
  const DgcnnMapClassifier& classifier = *mapper.classifier().accumulated_map();
  const LabelledPointMap& map = classifier.map();
  const std::vector<ClassId>& classes = classifier.channel_classes();
  ASSERT_EQ(classes.size(), 13u);
  std::map<std::uint64_t, std::array<double, kClassCount>> sums;
  std::map<std::uint64_t, std::vector<double>> logit_sums;
  std::vector<float> mean(classes.size());
  for (std::uint32_t p = 0; p < map.size(); ++p) {
    const std::uint32_t scored = map.scored_point(p);
    if (scored == LabelledPointMap::kNoPoint) continue;
    map.mean_scores(scored, mean.data());
    const double inv = 1.0 / config.voxel;
    auto& s = sums[metric::pack(
        metric::key_of(map.points().x()[p], map.points().y()[p], map.points().z()[p], inv))];
    for (std::size_t c = 0; c < classes.size(); ++c) s[static_cast<std::size_t>(classes[c])] += mean[c];
    auto& l = logit_sums[metric::pack(
        metric::key_of(map.points().x()[p], map.points().y()[p], map.points().z()[p], inv))];
    l.resize(classes.size());
    for (std::size_t c = 0; c < classes.size(); ++c) l[c] += mean[c];
  }
  std::size_t occupied = 0, agree = 0, single_logit_differs = 0;
  for (const auto& [word, s] : sums) {
    const metric::VoxelKey key = metric::unpack_voxel(word);
    if (mapper.metric_map().state(key) != metric::VoxelState::Occupied) continue;
    ++occupied;
    const auto best = static_cast<ClassId>(std::max_element(s.begin() + 1, s.end()) - s.begin());
    agree += mapper.metric_map().class_of(key) == best;
    const std::vector<double>& l = logit_sums[word];
    single_logit_differs +=
        classes[static_cast<std::size_t>(std::max_element(l.begin(), l.end()) - l.begin())] != best;
  }
  ASSERT_GT(occupied, 100u);
  EXPECT_GE(agree, occupied * 99 / 100) << agree << " of " << occupied;
  // The rule matters here: in many voxels the single highest logit is another class's.
  EXPECT_GT(single_logit_differs, occupied / 20) << single_logit_differs << " of " << occupied;
}

TEST(MapperMapClasses, PerScanClassificationStaysAvailable) {
  MapperConfig config = map_classifier_config();
  config.classifier.per_scan = true;
  Mapper mapper(config);
  integrate_room(mapper, 2);
  EXPECT_EQ(mapper.classifier().accumulated_map(), nullptr);
  EXPECT_FALSE(mapper.classifier().labels_arrive_late());
  EXPECT_GT(mapper.profile().counter("classify", "blocks"), 0.0);
}

TEST(MapperMapClasses, ABoundedMapForgetsLabelledPointsWithItsBlocks) {
  MapperConfig config = map_classifier_config();
  config.bounds.keep_radius = 1.0;
  Mapper mapper(config);
  integrate_room(mapper, 6);
  mapper.forget_dropped_regions();
  const DgcnnMapClassifier* classifier = mapper.classifier().accumulated_map();
  ASSERT_NE(classifier, nullptr);
  const LabelledPointMap& map = classifier->map();
  for (std::uint32_t p = 0; p < map.size(); ++p) {
    const auto key = metric::key_of(map.points().x()[p], map.points().y()[p], map.points().z()[p],
                                    mapper.metric_map().inv_resolution());
    EXPECT_TRUE(mapper.metric_map().blocks().voxel(key).has_value()) << p;
  }
  if (mapper.blocks_dropped() > 0) {
    EXPECT_GT(mapper.profile().counter("classify", "map_points_forgotten"), 0.0);
  }
}

}  // namespace
}  // namespace sarmap::pipeline
