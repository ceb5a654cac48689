// Tests `sarmap classify INPUT --model M --out OUT` (cloud mode of
// tools/sarmap/classify_command.cpp) by running the built binary on a small
// labelled PLY: the output keeps every point, has valid labels and per-class
// scores, and carries the input labels as gt_label; one frame of a sequence
// (--frame) is classified in the world frame; the rule chain runs after the
// network and --disable-rule turns rules off by name; --classifier geometric
// labels as the baseline does in process; bad invocations fail.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/classes.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/semantic/geometric/geometric_classifier.hpp"
#include "engine/semantic/rules/rule_chain.hpp"
#include "tests/file_bytes.hpp"
#include "tests/release_only.hpp"
#include "tests/semantic/dgcnn_test_data.hpp"
#include "tests/semantic/fixture_model.hpp"

namespace sarmap {
namespace {

using test::slurp;

namespace fs = std::filesystem;
using testing::kDgcnnDataDir;

int run_classify(const std::string& args, const fs::path& err) {
  const std::string cmd = std::string(SARMAP_CLI_PATH) + " classify " + args + " > /dev/null 2> " + err.string();
  return std::system(cmd.c_str());
}

// classify takes run's option names and defaults: blocks of 100 points are
// classified unless --min-block-points (or its older name --min-points) asks
// for more, and without --model the shipped ramp model is used.
TEST(ClassifyCloud, SharesRunsOptionNamesDefaultsAndModel) {
  const fs::path dir = fs::temp_directory_path() / ("sarmap_classify_names_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 0.999f);
  PointBuffer cloud;
  for (int i = 0; i < 800; ++i) cloud.push_back(u(rng), u(rng), 0.01f * u(rng));
  for (int i = 0; i < 150; ++i) cloud.push_back(4.0f + 0.5f * u(rng), 0.5f * u(rng), 0.0f);  // a block of 150 points
  write_point_cloud(dir / "in.ply", cloud);
  const auto labelled_in_small_block = [&](const std::string& options) {
    EXPECT_EQ(run_classify((dir / "in.ply").string() + " --out " + (dir / "out.ply").string() + " " + options, dir / "err"), 0)
        << options << ": " << slurp(dir / "err");
    const PointBuffer out = read_point_cloud(dir / "out.ply");
    std::size_t labelled = 0;
    for (std::size_t p = 800; p < out.size(); ++p) labelled += out.labels()[p] != 0;
    return labelled;
  };
  const std::string model = "--model " + test::fixture_model_c6().string();
  EXPECT_EQ(labelled_in_small_block(model), 150u);
  EXPECT_EQ(labelled_in_small_block(model + " --min-block-points 200"), 0u);
  EXPECT_EQ(labelled_in_small_block(model + " --min-points 200"), 0u);
  EXPECT_EQ(labelled_in_small_block(model + " --block-stride 1"), 150u);
  EXPECT_EQ(labelled_in_small_block(""), 150u);  // the shipped model
  fs::remove_all(dir);
}

TEST(ClassifyCloud, WritesLabelsScoresAndGroundTruth) {
  const fs::path dir = fs::temp_directory_path() / ("sarmap_classify_cloud_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0.0f, 0.999f);
  PointBuffer cloud;
  for (int i = 0; i < 800; ++i) cloud.push_back(u(rng), u(rng), 0.01f * u(rng));
  for (int i = 0; i < 50; ++i) cloud.push_back(4.0f + u(rng), u(rng), 0.0f);  // dropped block
  cloud.enable_labels();
  for (std::size_t p = 0; p < cloud.size(); ++p) cloud.labels()[p] = 1;
  write_point_cloud(dir / "in.ply", cloud);

  ASSERT_EQ(run_classify((dir / "in.ply").string() + " --model " + kDgcnnDataDir + "model_c6.safetensors --out " +
                    (dir / "out.ply").string() + " --threads 2",
                dir / "err"),
            0)
      << slurp(dir / "err");
  const PointBuffer out = read_point_cloud(dir / "out.ply");
  ASSERT_EQ(out.size(), cloud.size());
  ASSERT_TRUE(out.has_labels());
  ASSERT_TRUE(out.has_gt_labels());
  EXPECT_EQ(out.score_count(), 4u);
  for (std::size_t p = 0; p < out.size(); ++p) {
    EXPECT_EQ(out.gt_labels()[p], 1);
    if (p < 800) {
      EXPECT_GE(out.labels()[p], 1);
      EXPECT_LE(out.labels()[p], 4);
    } else {
      EXPECT_EQ(out.labels()[p], 0);
    }
  }
  fs::remove_all(dir);
}

// The rules after the network are `sarmap run`'s chain (RuleChain): the
// output with every rule on equals the output with every rule off taken
// through the chain in the test; `--disable-rule` names them, and an
// unknown name is a usage error listing the rules.
TEST(ClassifyCloud, RunsTheRuleChainAfterTheNetworkAndDisablesRulesByName) {
  RELEASE_ONLY();  // three DGCNN runs of the CLI: almost a minute under ASan, for the rule options
  const fs::path dir = fs::temp_directory_path() / ("sarmap_classify_rules_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  PointBuffer cloud;  // a floor, a wall along it and a 20-degree ramp on it, on a 3 cm grid
  for (float x = 0.0f; x < 2.4f; x += 0.03f) {
    for (float y = 0.0f; y < 2.4f; y += 0.03f) cloud.push_back(x, y, 0.0f);
    for (float z = 0.03f; z < 1.2f; z += 0.03f) cloud.push_back(x, 2.4f, z);
  }
  for (float x = 0.5f; x < 1.5f; x += 0.03f) {
    for (float y = 0.5f; y < 1.1f; y += 0.03f) cloud.push_back(x, y, 0.364f * (x - 0.5f));
  }
  write_point_cloud(dir / "in.ply", cloud);
  const std::string common = (dir / "in.ply").string() + " --model " + kDgcnnDataDir + "model_c6.safetensors --out ";
  ASSERT_EQ(run_classify(common + (dir / "ruled.ply").string(), dir / "err"), 0) << slurp(dir / "err");
  ASSERT_EQ(run_classify(common + (dir / "plain.ply").string() +
                             " --disable-rule ramp_veto --disable-rule wall_bands --disable-rule ramp_sides "
                             "--disable-rule wall_feet",
                         dir / "err"),
            0)
      << slurp(dir / "err");
  const PointBuffer ruled = read_point_cloud(dir / "ruled.ply");
  PointBuffer expected = read_point_cloud(dir / "plain.ply");
  RuleChain chain({});
  const RuleChanges changes = chain.apply(expected);
  ASSERT_EQ(ruled.size(), expected.size());
  ASSERT_EQ(ruled.score_count(), expected.score_count());
  for (std::size_t p = 0; p < ruled.size(); ++p) {
    ASSERT_EQ(ruled.labels()[p], expected.labels()[p]) << p;
    for (std::size_t c = 0; c < ruled.score_count(); ++c) ASSERT_EQ(ruled.score(c)[p], expected.score(c)[p]) << p;
  }
  EXPECT_GT(changes.total(), 0u) << "the scene gives the rules nothing to change";

  const std::string summary = (dir / "summary.txt").string();
  ASSERT_EQ(std::system((std::string(SARMAP_CLI_PATH) + " classify " + common + (dir / "some.ply").string() +
                         " --disable-rule wall_feet --disable-rule ramp_veto > " + summary + " 2>&1")
                            .c_str()),
            0);
  const std::string said = slurp(summary);
  EXPECT_NE(said.find("ramp_veto 0,"), std::string::npos) << said;
  EXPECT_NE(said.find("wall_feet 0\n"), std::string::npos) << said;

  const int status = run_classify(common + (dir / "bad.ply").string() + " --disable-rule wall_legs", dir / "err");
  EXPECT_EQ(WEXITSTATUS(status), 2);
  EXPECT_NE(slurp(dir / "err").find("wall_legs"), std::string::npos) << slurp(dir / "err");
  EXPECT_FALSE(fs::exists(dir / "bad.ply"));
  fs::remove_all(dir);
}

// `--classifier geometric` labels any cloud (a scan, or a run's accumulated
// semantic_points.ply) as GeometricClassifier with `sarmap run`'s settings
// does, keeps the input labels as gt_label, and refuses the DGCNN's options.
TEST(ClassifyCloud, GeometricBaselineLabelsAsInProcessAndRefusesNetworkOptions) {
  const fs::path dir = fs::temp_directory_path() / ("sarmap_classify_geometric_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  PointBuffer cloud;  // a floor and a wall along it on a 3 cm grid, labelled as the truth
  for (float x = 0.0f; x < 2.4f; x += 0.03f) {
    for (float y = 0.0f; y < 2.4f; y += 0.03f) cloud.push_back(x, y, 0.0f);
    for (float z = 0.03f; z < 1.2f; z += 0.03f) cloud.push_back(x, 2.4f, z);
  }
  cloud.enable_labels();
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    cloud.labels()[p] = static_cast<std::uint8_t>(cloud.z()[p] == 0.0f ? ClassId::Terrain : ClassId::Wall);
  }
  write_point_cloud(dir / "in.ply", cloud);
  const std::string in = (dir / "in.ply").string() + " --classifier geometric --out ";
  ASSERT_EQ(run_classify(in + (dir / "out.ply").string(), dir / "err"), 0) << slurp(dir / "err");
  const PointBuffer out = read_point_cloud(dir / "out.ply");
  PointBuffer expected = cloud;
  GeometricClassifier{}.classify(expected);
  ASSERT_EQ(out.size(), cloud.size());
  ASSERT_TRUE(out.has_gt_labels());
  EXPECT_EQ(out.score_count(), 0u);
  std::size_t right = 0;
  for (std::size_t p = 0; p < out.size(); ++p) {
    ASSERT_EQ(out.labels()[p], expected.labels()[p]) << p;
    ASSERT_EQ(out.gt_labels()[p], cloud.labels()[p]) << p;
    right += out.labels()[p] == cloud.labels()[p];
  }
  EXPECT_GT(right, out.size() * 9 / 10) << "a floor and a wall the baseline should get right";
  const std::string model = "--model " + kDgcnnDataDir + "model_c6.safetensors";
  for (const std::string& option : {model, std::string("--disable-rule wall_feet"), std::string("--block-stride 1")}) {
    EXPECT_EQ(WEXITSTATUS(run_classify(in + (dir / "bad.ply").string() + " " + option, dir / "err")), 1) << option;
    EXPECT_NE(slurp(dir / "err").find("DGCNN option"), std::string::npos) << slurp(dir / "err");
    EXPECT_FALSE(fs::exists(dir / "bad.ply"));
  }
  EXPECT_EQ(WEXITSTATUS(run_classify(in + (dir / "bad.ply").string() + " --classifier svm", dir / "err")), 2);
  fs::remove_all(dir);
}

TEST(ClassifyCloud, RefusesMissingOutAndBothModes) {
  const fs::path err = fs::temp_directory_path() / ("sarmap_classify_err_" + std::to_string(::getpid()));
  EXPECT_NE(run_classify(kDgcnnDataDir + "block_c6_n1024.npy --model " + kDgcnnDataDir + "model_c6.safetensors", err), 0);
  EXPECT_NE(run_classify(kDgcnnDataDir + "model_c6.safetensors --raw-block " + kDgcnnDataDir + "block_c6_n1024.npy --model " + kDgcnnDataDir +
                    "model_c6.safetensors --logits /dev/null",
                err),
            0);
  EXPECT_NE(slurp(err).find("either INPUT"), std::string::npos) << slurp(err);
  for (const char* stride : {"-1", "nan", "inf"}) {
    EXPECT_NE(run_classify(kDgcnnDataDir + "block_c6_n1024.npy --model " + kDgcnnDataDir + "model_c6.safetensors --out /tmp/never.ply --stride " +
                      stride,
                  err),
              0)
        << stride;
    EXPECT_NE(slurp(err).find("--block-stride: must be a finite number >= 0"), std::string::npos) << slurp(err);
  }
  fs::remove(err);
}

// `model` with the string `entry` added to its metadata, written to `out`.
void write_with_metadata(const std::string& model, const std::string& key, const std::string& value,
                         const fs::path& out) {
  const std::string bytes = slurp(model);
  std::uint64_t len = 0;
  for (int i = 0; i < 8; ++i)
    len |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[i])) << (8 * i);
  nlohmann::json header = nlohmann::json::parse(bytes.substr(8, len));
  header["__metadata__"][key] = value;
  const std::string text = header.dump();
  std::string head(8, '\0');
  for (int i = 0; i < 8; ++i) head[i] = static_cast<char>(static_cast<std::uint64_t>(text.size()) >> (8 * i));
  std::ofstream(out, std::ios::binary) << head << text << bytes.substr(8 + len);
}

// A model with another class list (the 13-class S3DIS fixture): every point
// gets a sarmap class and the scores are per sarmap class; a sarmap.class_map
// in the file is honoured, and one naming no sarmap class is refused by name.
TEST(ClassifyCloud, ModelWithAnotherClassListLabelsWithSarmapClasses) {
  const fs::path dir = fs::temp_directory_path() / ("sarmap_classify_s3dis_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::mt19937 rng(10);
  std::uniform_real_distribution<float> u(0.0f, 0.999f);
  PointBuffer cloud;
  for (int i = 0; i < 1500; ++i) cloud.push_back(1.9f * u(rng), 0.9f * u(rng), 0.01f * u(rng));
  for (int i = 0; i < 700; ++i) cloud.push_back(1.9f * u(rng), 0.95f, 1.2f * u(rng));
  write_point_cloud(dir / "in.ply", cloud);
  const std::string s3dis = kDgcnnDataDir + "model_s3dis13.safetensors";
  const auto classify = [&](const std::string& model) {
    EXPECT_EQ(run_classify((dir / "in.ply").string() + " --model " + model + " --out " + (dir / "out.ply").string(),
                  dir / "err"),
              0)
        << slurp(dir / "err");
    return read_point_cloud(dir / "out.ply");
  };
  const PointBuffer out = classify(s3dis);
  ASSERT_EQ(out.size(), cloud.size());
  EXPECT_EQ(out.score_names(), (std::vector<std::string>{"terrain", "wall", "other"}));
  for (std::size_t p = 0; p < out.size(); ++p) {
    const auto label = static_cast<ClassId>(out.labels()[p]);
    // The rules may move labels to the ramp classes; never beyond sarmap's.
    EXPECT_LT(out.labels()[p], kClassCount) << p;
    EXPECT_NE(label, ClassId::Unknown) << p;
  }

  nlohmann::json all_wall = nlohmann::json::object();
  for (const char* name : {"ceiling", "floor", "wall", "beam", "column", "window", "door", "table", "chair",
                           "sofa", "bookcase", "board", "clutter"}) {
    all_wall[name] = "wall";
  }
  write_with_metadata(s3dis, "sarmap.class_map", all_wall.dump(), dir / "walls.safetensors");
  const PointBuffer walls = classify((dir / "walls.safetensors").string());
  ASSERT_EQ(walls.score_names(), std::vector<std::string>{"wall"});
  for (std::size_t p = 0; p < walls.size(); ++p) {
    EXPECT_EQ(walls.labels()[p], static_cast<std::uint8_t>(ClassId::Wall)) << p;
    EXPECT_NEAR(walls.score(0)[p], 1.0f, 1e-4f) << p;
  }

  write_with_metadata(s3dis, "sarmap.class_map", R"({"ceiling": "roof"})", dir / "bad.safetensors");
  EXPECT_NE(run_classify((dir / "in.ply").string() + " --model " + (dir / "bad.safetensors").string() + " --out " +
                    (dir / "bad.ply").string(),
                dir / "err"),
            0);
  const std::string message = slurp(dir / "err");
  EXPECT_NE(message.find("sarmap.class_map"), std::string::npos) << message;
  EXPECT_NE(message.find("\"ceiling\": \"roof\" is not"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(dir / "bad.ply"));
  fs::remove_all(dir);
}

// One frame of a sequence folder, in the world frame (frame 1 of the tiny
// sequence is posed at (3, 4) and holds 2 points); a frame past the end is refused.
TEST(ClassifyCloud, ClassifiesOneFrameOfASequence) {
  const fs::path dir = fs::temp_directory_path() / ("sarmap_classify_frame_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string seq = std::string(SARMAP_TEST_DATA_DIR) + "/sequences/tiny";
  const PointBuffer sensor_frame = read_point_cloud(seq + "/frame_000001.ply");
  ASSERT_EQ(run_classify(seq + " --frame 1 --model " + kDgcnnDataDir + "model_c6.safetensors --out " + (dir / "f1.ply").string(),
                dir / "err"),
            0)
      << slurp(dir / "err");
  const PointBuffer out = read_point_cloud(dir / "f1.ply");
  ASSERT_EQ(out.size(), sensor_frame.size());
  ASSERT_TRUE(out.has_labels());
  for (std::size_t p = 0; p < out.size(); ++p) {
    // pose: x' = -y + 3, y' = x + 4
    EXPECT_NEAR(out.x()[p], -sensor_frame.y()[p] + 3.0f, 1e-5f);
    EXPECT_NEAR(out.y()[p], sensor_frame.x()[p] + 4.0f, 1e-5f);
    EXPECT_EQ(out.labels()[p], 0) << "two points are far too few for a block";
  }
  EXPECT_NE(run_classify(seq + " --frame 2 --model " + kDgcnnDataDir + "model_c6.safetensors --out " + (dir / "f2.ply").string(),
                dir / "err"),
            0);
  EXPECT_NE(slurp(dir / "err").find("--frame 2 but the sequence has 2 frames"), std::string::npos)
      << slurp(dir / "err");
  EXPECT_FALSE(fs::exists(dir / "f2.ply"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sarmap
