// Tests of engine/eval/point_evaluation.hpp and run_evaluation.hpp: scoring
// a cloud's label against gt_label, and a run folder with or without outputs.
#include "engine/eval/point_evaluation.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/eval/run_evaluation.hpp"
#include "engine/io/ply.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/sim/arena.hpp"

namespace sarmap::eval {
namespace {

// predicted / truth pairs: 2 right terrain, 1 unlabelled wall, 1 right wall,
// 1 inclined taken for flat, 1 point without ground truth.
PointBuffer classified_cloud() {
  PointBuffer p(6);
  p.enable_labels();
  p.enable_gt_labels();
  const std::uint8_t predicted[] = {1, 1, 0, 2, 4, 2};
  const std::uint8_t truth[] = {1, 1, 2, 2, 3, 0};
  for (std::size_t i = 0; i < 6; ++i) {
    p.labels()[i] = predicted[i];
    p.gt_labels()[i] = truth[i];
    p.x()[i] = static_cast<float>(i);
  }
  return p;
}

TEST(PointEvaluation, ScoresLabelAgainstGroundTruth) {
  const PointEvaluation e = evaluate_points(classified_cloud(), "cloud");
  EXPECT_EQ(e.points, 6u);
  EXPECT_EQ(e.scored, 5u);
  EXPECT_EQ(e.unlabelled, 1u);
  EXPECT_DOUBLE_EQ(*e.confusion.accuracy(), 3.0 / 5.0);
  EXPECT_DOUBLE_EQ(*e.confusion.iou(ClassId::Terrain), 1.0);
  EXPECT_DOUBLE_EQ(*e.confusion.iou(ClassId::Wall), 0.5);
  EXPECT_DOUBLE_EQ(*e.confusion.iou(ClassId::InclinedRamp), 0.0);
  EXPECT_DOUBLE_EQ(*e.confusion.iou(ClassId::FlatRamp), 0.0);
  EXPECT_DOUBLE_EQ(*e.confusion.mean_iou(), 0.375);
}

TEST(PointEvaluation, RejectsCloudsItCannotScore) {
  PointBuffer no_truth(2);
  no_truth.enable_labels();
  EXPECT_THROW(evaluate_points(no_truth, "a.ply"), Error);
  PointBuffer bad = classified_cloud();
  bad.labels()[3] = 9;
  try {
    evaluate_points(bad, "b.ply");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("b.ply: point 3 has label 9"), std::string::npos) << e.what();
  }
}

class RunFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("sarmap_eval_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    arena_ = sim::load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
  sim::Arena arena_;
};

TEST_F(RunFolder, ScoresSemanticPointsAndNamesAbsentFiles) {
  {
    RunFolderWriter folder(dir_);
    write_ply(dir_ / "semantic_points.ply", classified_cloud());
    folder.commit(nlohmann::ordered_json::object(), {"semantic_points.ply"});
  }
  const RunEvaluation e = evaluate_run(arena_, dir_);
  EXPECT_EQ(e.arena_name, "esogu-6x4");
  ASSERT_TRUE(e.points.has_value());
  EXPECT_EQ(e.points->scored, 5u);
  ASSERT_EQ(e.files.size(), 4u);
  EXPECT_TRUE(e.files[0].present);
  EXPECT_FALSE(e.files[1].present);
  const auto j = nlohmann::json::parse(format_json(e));
  EXPECT_DOUBLE_EQ(j.at("accuracy").get<double>(), 0.6);
  EXPECT_DOUBLE_EQ(j.at("mean_iou").get<double>(), 0.375);
  EXPECT_DOUBLE_EQ(j.at("per_class_iou").at("wall").get<double>(), 0.5);
  EXPECT_TRUE(j.at("per_class_iou").at("other").is_null());
  EXPECT_EQ(j.at("confusion").at("matrix")[2][0].get<int>(), 1);  // wall taken for unknown
  EXPECT_EQ(j.at("points_unlabelled").get<int>(), 1);
  EXPECT_EQ(j.at("absent"), nlohmann::json({"map.sarmap", "segments.json", "graph.json"}));
  EXPECT_FALSE(j.contains("segments"));
  const std::string table = format_table(e);
  EXPECT_NE(table.find("accuracy  60.00%"), std::string::npos) << table;
  EXPECT_NE(table.find("map.sarmap: absent"), std::string::npos) << table;
}

TEST_F(RunFolder, EmptyRunReportsWhatIsMissing) {
  RunFolderWriter(dir_).commit(nlohmann::ordered_json::object(), {});
  const RunEvaluation e = evaluate_run(arena_, dir_);
  EXPECT_FALSE(e.points.has_value());
  // The arena could not be checked (the manifest names none), then one note per absent file.
  ASSERT_EQ(e.notes.size(), 5u);
  EXPECT_NE(e.notes[0].find("records no arena"), std::string::npos) << e.notes[0];
  EXPECT_EQ(e.notes[3], "segments.json absent: no segment figures");
  const auto j = nlohmann::json::parse(format_json(e));
  EXPECT_FALSE(j.contains("accuracy"));
  EXPECT_EQ(j.at("absent").size(), 4u);
  EXPECT_THROW(evaluate_run(arena_, dir_ / "missing"), Error);
}

}  // namespace
}  // namespace sarmap::eval
