// Voxel scoring on a hand-built map against a hand-built ground truth, where
// every count can be worked out on paper.
#include "engine/eval/voxel_scores.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"

namespace sarmap::eval {
namespace {

using metric::MetricMap;
using metric::VoxelKey;

MetricMap empty_map(double resolution) {
  metric::MetricMapSettings settings;
  settings.resolution = resolution;
  return MetricMap(settings);
}

void set_voxel(MetricMap& map, const VoxelKey& k, bool occupied, ClassId cls = ClassId::Unknown) {
  metric::SemanticVoxel v = map.blocks().voxel(k).value_or(metric::SemanticVoxel{});
  v.log_odds = occupied ? map.occupancy().max() : map.occupancy().min();
  if (cls != ClassId::Unknown) v.evidence[static_cast<std::size_t>(cls)] = 120;
  map.blocks().set_voxel(k, v);
}

void add_truth(sim::GroundTruthGrid& truth, const sim::VoxelKey& k, ClassId cls, bool observed) {
  sim::OccupiedVoxel v;
  v.label = cls;
  v.observed = observed;
  truth.occupied[k] = v;
}

// Keys straddle block boundaries and negative coordinates, where a mix-up of
// block and voxel keys would show.
class HandBuilt : public ::testing::Test {
 protected:
  void SetUp() override {
    truth.resolution = 0.1;
    add_truth(truth, {-1, -1, -1}, ClassId::Wall, true);      // A
    add_truth(truth, {0, -1, -1}, ClassId::Wall, true);       // B
    add_truth(truth, {5, 5, 7}, ClassId::Terrain, true);      // C
    add_truth(truth, {9, 9, 9}, ClassId::Terrain, false);     // D, never seen
    add_truth(truth, {30, 30, 30}, ClassId::Unknown, false);  // no class, not seen
    truth.free = {{-1, -1, 1}, {-1, -1, 2}, {-1, -1, 3}};

    set_voxel(map, {-1, -1, -1}, true, ClassId::Wall);    // A, right class
    set_voxel(map, {0, -1, -1}, true, ClassId::Terrain);  // B, wrong class
    set_voxel(map, {5, 5, 8}, true, ClassId::Terrain);    // one voxel above C
    set_voxel(map, {20, 20, 20}, true, ClassId::Wall);    // nowhere near a surface
    set_voxel(map, {-1, -1, 1}, false);                   // truth free
    set_voxel(map, {-1, -1, 2}, false);                   // truth free
    set_voxel(map, {-1, -1, 4}, false);                   // truth unknown
    set_voxel(map, {9, 9, 9}, false);                     // D carved free
  }
  MetricMap map = empty_map(0.1);
  sim::GroundTruthGrid truth;
};

TEST_F(HandBuilt, CountsEveryCase) {
  const VoxelScores s = score_voxels(map, truth);
  EXPECT_EQ(s.map_occupied, 4u);
  EXPECT_EQ(s.map_free, 4u);
  EXPECT_EQ(s.truth_occupied, 5u);
  EXPECT_EQ(s.truth_observed, 3u);
  EXPECT_EQ(s.truth_free, 3u);
  EXPECT_EQ(s.occupied_correct, 2u);           // A, B
  EXPECT_EQ(s.occupied_correct_within_1, 3u);  // and the voxel above C
  EXPECT_EQ(s.observed_found, 2u);             // A, B
  EXPECT_EQ(s.observed_found_within_1, 3u);    // and C through its neighbour
  EXPECT_EQ(s.free_found, 2u);
  EXPECT_EQ(s.map_free_truth_free, 2u);
  EXPECT_EQ(s.map_free_on_surface, 1u);  // D
  EXPECT_EQ(s.classes.total(), 2u);
  EXPECT_EQ(s.classes.count(ClassId::Wall, ClassId::Wall), 1u);
  EXPECT_EQ(s.classes.count(ClassId::Wall, ClassId::Terrain), 1u);
}

TEST_F(HandBuilt, Figures) {
  const VoxelScores s = score_voxels(map, truth);
  EXPECT_DOUBLE_EQ(*s.precision(), 0.5);
  EXPECT_DOUBLE_EQ(*s.recall(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(*s.f1(), 2 * 0.5 * (2.0 / 3.0) / (0.5 + 2.0 / 3.0));
  EXPECT_DOUBLE_EQ(*s.precision_within_1(), 0.75);
  EXPECT_DOUBLE_EQ(*s.recall_within_1(), 1.0);
  EXPECT_DOUBLE_EQ(*s.f1_within_1(), 2 * 0.75 / 1.75);
  EXPECT_DOUBLE_EQ(*s.free_accuracy(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(*s.free_precision(), 0.5);
  EXPECT_DOUBLE_EQ(*s.class_accuracy(), 0.5);
}

TEST_F(HandBuilt, JsonKeys) {
  nlohmann::ordered_json j;
  add_voxel_scores_json(score_voxels(map, truth), j);
  EXPECT_DOUBLE_EQ(j.at("voxel_precision").get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j.at("voxel_recall_within_1").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j.at("free_accuracy").get<double>(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(j.at("voxel_class_accuracy").get<double>(), 0.5);
  EXPECT_EQ(j.at("voxel_counts").at("map_free_on_surface").get<int>(), 1);
  EXPECT_EQ(j.at("voxel_class_confusion").at("matrix").at(2).at(1).get<int>(), 1);  // wall taken for terrain
}

TEST(VoxelScores, EmptyMapHasNoPrecisionAndZeroRecall) {
  const MetricMap map = empty_map(0.1);
  sim::GroundTruthGrid truth;
  truth.resolution = 0.1;
  add_truth(truth, {1, 2, 3}, ClassId::Wall, true);
  const VoxelScores s = score_voxels(map, truth);
  EXPECT_FALSE(s.precision().has_value());
  EXPECT_DOUBLE_EQ(*s.recall(), 0.0);
  EXPECT_FALSE(s.f1().has_value());
  EXPECT_FALSE(s.free_accuracy().has_value());
  EXPECT_FALSE(s.class_accuracy().has_value());
  nlohmann::ordered_json j;
  add_voxel_scores_json(s, j);
  EXPECT_TRUE(j.at("voxel_precision").is_null());
}

TEST(VoxelScores, RejectsAnotherResolution) {
  const MetricMap map = empty_map(0.05);
  sim::GroundTruthGrid truth;
  truth.resolution = 0.1;
  EXPECT_THROW(score_voxels(map, truth), Error);
}

}  // namespace
}  // namespace sarmap::eval
