// Tests DgcnnClassifier end to end on a small cloud with the fixture model:
// valid class ids, scores that are probabilities, dropped points unknown, and
// identical results for 1 and 2 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <tbb/global_control.h>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/semantic/dgcnn/dgcnn_classifier.hpp"

#include "tests/semantic/fixture_model.hpp"

namespace sarmap {
namespace {

PointBuffer small_scene() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 0.999f);
  PointBuffer cloud;
  for (int i = 0; i < 1500; ++i) cloud.push_back(u(rng), u(rng), 0.02f * u(rng));         // floor block
  for (int i = 0; i < 900; ++i) cloud.push_back(1.7f, 0.0f + u(rng), 1.2f * u(rng));       // wall block
  for (int i = 0; i < 100; ++i) cloud.push_back(5.0f + u(rng), 5.0f + u(rng), 0.0f);       // too sparse
  cloud.enable_gt_labels();
  return cloud;
}

// No overlap: one block of the floor, one of the wall.
DgcnnClassifierSettings one_block_per_cell(const DgcnnModel& model) {
  DgcnnClassifierSettings settings;
  settings.stride = model.metadata().block_size;
  return settings;
}

TEST(DgcnnClassifier, ByDefaultBlocksOverlapByAQuarter) {
  const DgcnnModel model = DgcnnModel::load(test::fixture_model_c6());
  DgcnnClassifierSettings quarter;
  quarter.stride = kDefaultStrideFraction * model.metadata().block_size;
  PointBuffer by_default = small_scene(), by_quarter = small_scene(), apart = small_scene();
  const DgcnnClassifyStats d = DgcnnClassifier(model, {}).classify(by_default);
  const DgcnnClassifyStats q = DgcnnClassifier(model, quarter).classify(by_quarter);
  const DgcnnClassifyStats a = DgcnnClassifier(model, one_block_per_cell(model)).classify(apart);
  EXPECT_EQ(kDefaultStrideFraction, 0.75);
  EXPECT_EQ(d.blocks, q.blocks);
  EXPECT_GT(d.blocks, a.blocks);
  EXPECT_TRUE(std::equal(by_default.labels().begin(), by_default.labels().end(), by_quarter.labels().begin()));
  for (std::size_t c = 0; c < by_default.score_count(); ++c) {
    EXPECT_TRUE(std::equal(by_default.score(c).begin(), by_default.score(c).end(), by_quarter.score(c).begin())) << c;
  }
}

// The neighbour search is quadratic: a 200,000-point raw block ran for minutes.
TEST(DgcnnModel, RefusesBlocksBeyondTheLimitBeforeAnyWork) {
  const DgcnnModel model = DgcnnModel::load(test::fixture_model_c6());
  const std::size_t n = DgcnnModel::kMaxBlockPoints + 1;
  const std::vector<float> block(n * model.channels(), 0.0f);
  std::vector<float> logits(n * model.classes());
  DgcnnWorkspace workspace;
  try {
    model.forward(block.data(), n, logits.data(), workspace);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::OutOfRange);
    EXPECT_NE(std::string(e.what()).find("a block of 16385 points; at most 16384"), std::string::npos) << e.what();
  }
}

TEST(DgcnnClassifier, LabelsEveryPointWithValidClassesAndProbabilities) {
  const DgcnnModel model = DgcnnModel::load(test::fixture_model_c6());
  const DgcnnClassifier classifier(model, one_block_per_cell(model));
  PointBuffer cloud = small_scene();
  const DgcnnClassifyStats stats = classifier.classify(cloud);
  EXPECT_EQ(stats.blocks, 2u);
  EXPECT_EQ(stats.dropped_points, 100u);
  ASSERT_TRUE(cloud.has_labels());
  ASSERT_EQ(cloud.score_count(), model.classes());
  EXPECT_EQ(cloud.score_names()[0], "terrain");
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    double sum = 0.0;
    for (std::size_t c = 0; c < cloud.score_count(); ++c) {
      EXPECT_GE(cloud.score(c)[p], 0.0f);
      sum += cloud.score(c)[p];
    }
    if (p >= 2400) {
      EXPECT_EQ(cloud.labels()[p], static_cast<std::uint8_t>(ClassId::Unknown));
      EXPECT_EQ(sum, 0.0);
    } else {
      EXPECT_NEAR(sum, 1.0, 1e-4);
      EXPECT_GE(cloud.labels()[p], 1);
      EXPECT_LE(cloud.labels()[p], model.classes());
      // The label is the arg-max of the scores.
      const std::size_t label_channel = cloud.find_score(std::string(class_info(static_cast<ClassId>(cloud.labels()[p])).name));
      for (std::size_t c = 0; c < cloud.score_count(); ++c) EXPECT_LE(cloud.score(c)[p], cloud.score(label_channel)[p]);
    }
  }
}

TEST(DgcnnClassifier, IndependentOfThreadCount) {
  const DgcnnModel model = DgcnnModel::load(test::fixture_model_c6());
  const DgcnnClassifier classifier(model, {});
  PointBuffer one = small_scene(), two = small_scene();
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    classifier.classify(one);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    classifier.classify(two);
  }
  for (std::size_t p = 0; p < one.size(); ++p) {
    ASSERT_EQ(one.labels()[p], two.labels()[p]);
    for (std::size_t c = 0; c < one.score_count(); ++c) ASSERT_EQ(one.score(c)[p], two.score(c)[p]);
  }
}

TEST(DgcnnClassifier, ColourModelNeedsColours) {
  const DgcnnModel model = DgcnnModel::load(SARMAP_TEST_DATA_DIR "/dgcnn/model_c9.safetensors");
  const DgcnnClassifier classifier(model, {});
  PointBuffer cloud = small_scene();
  EXPECT_THROW(classifier.classify(cloud), Error);
}

}  // namespace
}  // namespace sarmap
