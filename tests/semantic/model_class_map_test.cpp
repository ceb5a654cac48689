// Tests a model whose classes are not sarmap's (engine/semantic/dgcnn/
// dgcnn_metadata.hpp, class_probabilities.hpp): the S3DIS class list loads
// and maps onto sarmap's classes by default or by sarmap.class_map, a bad
// map is refused naming the key and the class, and both DGCNN classifiers
// label with the sum of each class's logit probabilities, checked against a
// plain reference on the 13-class fixture (tests/data/dgcnn/model_s3dis13).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/io/safetensors.hpp"
#include "engine/semantic/dgcnn/block_features.hpp"
#include "engine/semantic/dgcnn/block_partition.hpp"
#include "engine/semantic/dgcnn/block_sampling.hpp"
#include "engine/semantic/dgcnn/class_probabilities.hpp"
#include "engine/semantic/dgcnn/dgcnn_classifier.hpp"
#include "engine/semantic/dgcnn/score_carry_back.hpp"
#include "engine/semantic/map/dgcnn_map_classifier.hpp"
#include "kernels/simd_level.hpp"

namespace sarmap {
namespace {

const char* kS3dis = "ceiling,floor,wall,beam,column,window,door,table,chair,sofa,bookcase,board,clutter";

const DgcnnModel& s3dis_model() {
  static const DgcnnModel model = DgcnnModel::load(SARMAP_TEST_DATA_DIR "/dgcnn/model_s3dis13.safetensors");
  return model;
}

// The same weights with the logits spread over all five classes by a
// sarmap.class_map: by default 11 of the 13 count as other, whose summed
// probability then wins almost everywhere with random weights.
const DgcnnModel& spread_model() {
  static const DgcnnModel model = [] {
    const SafetensorsFile file =
        SafetensorsFile::read(SARMAP_TEST_DATA_DIR "/dgcnn/model_s3dis13.safetensors");
    std::map<std::string, std::string> entries = file.metadata();
    entries["sarmap.class_map"] =
        R"({"ceiling": "inclined_ramp", "beam": "flat_ramp", "column": "wall", "window": "terrain",
            "door": "inclined_ramp", "table": "flat_ramp", "chair": "terrain", "sofa": "wall"})";
    return DgcnnModel(load_dgcnn_weights(file), parse_dgcnn_metadata(entries, "spread"),
                      kernels::active_simd_level());
  }();
  return model;
}

std::string parse_error(const std::map<std::string, std::string>& entries) {
  try {
    parse_dgcnn_metadata(entries, "m.safetensors");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ModelClassMap, S3disNamesMapToSarmapClassesByDefault) {
  const DgcnnMetadata m = parse_dgcnn_metadata({{"sarmap.classes", kS3dis}}, "m");
  ASSERT_EQ(m.class_names.size(), 13u);
  EXPECT_EQ(m.class_names[0], "ceiling");
  ASSERT_EQ(m.classes.size(), 13u);
  for (std::size_t l = 0; l < 13; ++l) {
    const ClassId want = l == 1 ? ClassId::Terrain : l == 2 ? ClassId::Wall : ClassId::Other;
    EXPECT_EQ(m.classes[l], want) << m.class_names[l];
  }
  // sarmap's own names map to themselves, so the shipped models are unchanged.
  const DgcnnMetadata own =
      parse_dgcnn_metadata({{"sarmap.classes", "terrain,wall,inclined_ramp,flat_ramp,other"}}, "m");
  EXPECT_EQ(own.classes, (std::vector<ClassId>{ClassId::Terrain, ClassId::Wall, ClassId::InclinedRamp,
                                               ClassId::FlatRamp, ClassId::Other}));
  EXPECT_EQ(default_sarmap_class("ground"), ClassId::Terrain);
  EXPECT_EQ(default_sarmap_class("unknown"), ClassId::Other);
}

TEST(ModelClassMap, MetadataMapIsHonouredAndWrittenBack) {
  const std::map<std::string, std::string> entries{
      {"sarmap.classes", kS3dis}, {"sarmap.class_map", R"({"ceiling": "wall", "table": "flat_ramp"})"}};
  const DgcnnMetadata m = parse_dgcnn_metadata(entries, "m");
  EXPECT_EQ(m.classes[0], ClassId::Wall);
  EXPECT_EQ(m.classes[1], ClassId::Terrain);  // not in the map: the default
  EXPECT_EQ(m.classes[7], ClassId::FlatRamp);
  const auto written = dgcnn_metadata_entries(m);
  EXPECT_EQ(written.at("sarmap.classes"), kS3dis);
  const DgcnnMetadata again = parse_dgcnn_metadata(written, "again");
  EXPECT_EQ(again.classes, m.classes);
  EXPECT_EQ(again.class_names, m.class_names);
  // Identity models write no map.
  EXPECT_EQ(dgcnn_metadata_entries(parse_dgcnn_metadata({{"sarmap.classes", "terrain,wall"}}, "m"))
                .count("sarmap.class_map"),
            0u);
}

TEST(ModelClassMap, BadMapIsRefusedNamingTheKeyAndTheClass) {
  const auto error = [](const std::string& map) {
    return parse_error({{"sarmap.classes", kS3dis}, {"sarmap.class_map", map}});
  };
  const std::string lava = error(R"({"ceiling": "lava"})");
  EXPECT_NE(lava.find("sarmap.class_map"), std::string::npos) << lava;
  EXPECT_NE(lava.find("\"ceiling\": \"lava\" is not"), std::string::npos) << lava;
  const std::string unknown = error(R"({"ceiling": "unknown"})");
  EXPECT_NE(unknown.find("\"unknown\" is not"), std::string::npos) << unknown;
  const std::string roof = error(R"({"roof": "wall"})");
  EXPECT_NE(roof.find("sarmap.class_map"), std::string::npos) << roof;
  EXPECT_NE(roof.find("\"roof\" is not in sarmap.classes"), std::string::npos) << roof;
  for (const char* bad : {"[]", "{", R"({"ceiling": 3})"}) {
    EXPECT_NE(error(bad).find("sarmap.class_map"), std::string::npos) << bad;
  }
  EXPECT_NE(parse_error({{"sarmap.classes", "wall,,other"}}).find("an empty one"), std::string::npos);
}

TEST(ModelClassMap, ClassProbabilitiesSumPerClassAndPickTheLowestIdOnTies) {
  const std::vector<ClassId> logits{ClassId::Other, ClassId::Terrain, ClassId::Wall, ClassId::Other};
  const ClassProbabilities cp(logits);
  EXPECT_EQ(cp.classes(), (std::vector<ClassId>{ClassId::Terrain, ClassId::Wall, ClassId::Other}));
  const float row[4] = {0.2f, 0.35f, 0.05f, 0.4f};
  float out[3];
  cp.sum(row, out);
  EXPECT_FLOAT_EQ(out[0], 0.35f);
  EXPECT_FLOAT_EQ(out[1], 0.05f);
  EXPECT_FLOAT_EQ(out[2], 0.6f);
  EXPECT_EQ(cp.best(out), 2u);  // other wins though terrain has the highest single logit
  const float tie[3] = {0.4f, 0.2f, 0.4f};
  EXPECT_EQ(cp.best(tie), 0u);
}

// A floor, two walls and some boxes, with noise: random input for the model.
PointBuffer random_scene(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  PointBuffer cloud;
  for (int i = 0; i < 3000; ++i) cloud.push_back(2.9f * u(rng), 1.9f * u(rng), 0.01f * u(rng));
  for (int i = 0; i < 1200; ++i) cloud.push_back(2.9f * u(rng), 1.95f, 1.5f * u(rng));
  for (int i = 0; i < 800; ++i) cloud.push_back(2.95f, 1.9f * u(rng), 1.5f * u(rng));
  for (int i = 0; i < 600; ++i) cloud.push_back(1.0f + 0.4f * u(rng), 0.5f + 0.4f * u(rng), 0.4f * u(rng));
  return cloud;
}

// The plain reference: per sarmap class, the sum of its logits' probabilities;
// the label the highest (lowest class id first), unknown when nothing scored.
struct Reference {
  std::array<double, kClassCount> per_class{};
  ClassId label = ClassId::Unknown;
};
Reference reference(const std::vector<ClassId>& logit_classes, const float* probabilities, bool scored) {
  Reference r;
  if (!scored) return r;
  std::array<bool, kClassCount> present{};
  for (std::size_t l = 0; l < logit_classes.size(); ++l) {
    r.per_class[static_cast<std::size_t>(logit_classes[l])] += probabilities[l];
    present[static_cast<std::size_t>(logit_classes[l])] = true;
  }
  double best = -1.0;
  for (std::size_t c = 1; c < kClassCount; ++c) {
    if (present[c] && r.per_class[c] > best) best = r.per_class[c], r.label = static_cast<ClassId>(c);
  }
  return r;
}

// Per-logit mean probabilities of each point, computed as DgcnnClassifier
// does from the public steps (partition, sampling, features, forward,
// softmax, carry-back).
ScoreAccumulator per_logit_probabilities(const DgcnnModel& model, const PointBuffer& points,
                                         const DgcnnClassifierSettings& s) {
  const DgcnnMetadata& m = model.metadata();
  BlockPartitionSettings ps;
  ps.block_size = m.block_size;
  ps.stride = s.stride > 0.0 ? s.stride : kDefaultStrideFraction * m.block_size;
  ps.min_points = s.min_points;
  const BlockPartition part = partition_blocks(points, ps);
  const std::size_t classes = model.classes();
  ScoreAccumulator acc(points.size(), classes);
  DgcnnWorkspace workspace;
  for (std::size_t b = 0; b < part.blocks.size(); ++b) {
    const Block& block = part.blocks[b];
    const std::vector<std::uint32_t> samples =
        sample_block(block.points.size(), m.points_per_block, s.seed, b);
    std::vector<std::uint32_t> indices(samples.size());
    for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = block.points[samples[i]];
    const BlockFrame frame{block.origin_x, block.origin_y, block.size, m.z_min, m.z_max};
    const std::vector<float> features = block_features(points, indices, frame, false);
    std::vector<float> scores(indices.size() * classes);
    model.forward(features.data(), indices.size(), scores.data(), workspace);
    for (std::size_t i = 0; i < indices.size(); ++i) {
      float* row = scores.data() + i * classes;
      const float top = *std::max_element(row, row + classes);
      double sum = 0.0;
      for (std::size_t c = 0; c < classes; ++c) sum += (row[c] = std::exp(row[c] - top));
      for (std::size_t c = 0; c < classes; ++c) row[c] = static_cast<float>(row[c] / sum);
    }
    acc.add_block(points, block, samples, scores);
  }
  return acc;
}

// Both classifiers on both mappings: the default (terrain, wall, other) and
// one spread over all five classes, whose labels vary more.
struct Case {
  const DgcnnModel* model;
  std::vector<std::string> score_names;
};
std::vector<Case> cases() {
  return {{&s3dis_model(), {"terrain", "wall", "other"}},
          {&spread_model(), {"terrain", "wall", "inclined_ramp", "flat_ramp", "other"}}};
}

TEST(ModelClassMap, PerScanClassifierAgreesWithThePlainReference) {
  for (const Case& k : cases()) {
    const DgcnnModel& model = *k.model;
    ASSERT_EQ(model.classes(), 13u);
    DgcnnClassifierSettings s;
    s.min_points = 100;
    const DgcnnClassifier classifier(model, s);
    std::array<std::size_t, kClassCount> counts{};
    for (const unsigned seed : {1u, 2u, 3u}) {
      PointBuffer cloud = random_scene(seed);
      classifier.classify(cloud);
      ASSERT_EQ(cloud.score_names(), k.score_names);
      const ScoreAccumulator acc = per_logit_probabilities(model, cloud, s);
      std::vector<float> mean(13);
      std::size_t labelled = 0;
      for (std::size_t p = 0; p < cloud.size(); ++p) {
        acc.mean(p, mean.data());
        const Reference r = reference(model.metadata().classes, mean.data(), acc.hits(p) > 0);
        ASSERT_EQ(cloud.labels()[p], static_cast<std::uint8_t>(r.label)) << seed << " " << p;
        ++counts[cloud.labels()[p]];
        for (std::size_t c = 0; c < cloud.score_count(); ++c) {
          const ClassId id = *class_from_name(cloud.score_names()[c]);
          EXPECT_NEAR(cloud.score(c)[p], r.per_class[static_cast<std::size_t>(id)], 1e-5) << p;
        }
        labelled += r.label != ClassId::Unknown;
      }
      EXPECT_GT(labelled, cloud.size() / 2);
    }
    if (k.model == &spread_model()) {
      EXPECT_GT(std::count_if(counts.begin() + 1, counts.end(), [](std::size_t n) { return n > 0; }), 2);
    }
  }
}

TEST(ModelClassMap, AccumulatedMapClassifierAgreesWithThePlainReference) {
  for (const Case& k : cases()) {
    const DgcnnModel& model = *k.model;
    DgcnnMapClassifierSettings s;
    s.cell = 0.05;
    DgcnnMapClassifier classifier(model, s);
    std::array<std::size_t, kClassCount> counts{};
    for (const unsigned seed : {4u, 5u, 6u}) {
      PointBuffer scan = random_scene(seed);
      classifier.classify(scan);
      ASSERT_EQ(scan.score_names(), k.score_names);
      const LabelledPointMap& map = classifier.map();
      std::vector<float> mean(13);
      for (std::size_t i = 0; i < scan.size(); ++i) {
        const std::uint32_t own = map.find(scan.x()[i], scan.y()[i], scan.z()[i]);
        const std::uint32_t p = own == LabelledPointMap::kNoPoint ? own : map.scored_point(own);
        const bool scored = p != LabelledPointMap::kNoPoint && map.hits(p) > 0;
        if (scored) map.mean_scores(p, mean.data());
        const Reference r = reference(model.metadata().classes, mean.data(), scored);
        // The map labels from its exact integer sums: the reference too, so
        // that rounding cannot split a tie.
        std::vector<float> exact(13, 0.0f);
        if (scored) std::copy_n(map.score_sums(p).begin(), 13, exact.begin());
        const ClassId label = reference(model.metadata().classes, exact.data(), scored).label;
        ASSERT_EQ(scan.labels()[i], static_cast<std::uint8_t>(label)) << seed << " " << i;
        ASSERT_EQ(classifier.map_point_class(p), label);
        ++counts[scan.labels()[i]];
        for (std::size_t c = 0; c < scan.score_count(); ++c) {
          const ClassId id = *class_from_name(scan.score_names()[c]);
          EXPECT_NEAR(scan.score(c)[i], r.per_class[static_cast<std::size_t>(id)], 1e-5) << i;
        }
      }
    }
    EXPECT_GT(std::count_if(counts.begin() + 1, counts.end(), [](std::size_t n) { return n > 0; }),
              k.model == &spread_model() ? 2 : 0);
  }
}

}  // namespace
}  // namespace sarmap
