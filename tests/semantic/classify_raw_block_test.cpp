// Tests `sarmap classify --raw-block` (tools/sarmap/classify_command.cpp) by
// running the built binary: golden logits come back through .npy files, and
// a block of the wrong width is refused with a message and a non-zero exit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/io/npy.hpp"
#include "tests/semantic/dgcnn_test_data.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using testing::kDgcnnDataDir;

int run_classify_raw(const std::string& args, const fs::path& err) {
  const std::string cmd = std::string(SARMAP_CLI_PATH) + " classify " + args + " 2> " + err.string();
  return std::system(cmd.c_str());
}

TEST(ClassifyRawBlock, WritesLogitsMatchingTheReference) {
  const fs::path out = fs::temp_directory_path() / ("sarmap_logits_" + std::to_string(::getpid()) + ".npy");
  const fs::path err = out.string() + ".err";
  ASSERT_EQ(run_classify_raw("--raw-block " + kDgcnnDataDir + "block_c6_n1024.npy --model " + kDgcnnDataDir + "model_c6.safetensors --logits " +
                    out.string() + " --threads 2",
                err),
            0);
  const NpyArray got = read_npy_f32(out);
  const NpyArray want = read_npy_f32(kDgcnnDataDir + "logits_c6_n1024.npy");
  ASSERT_EQ(got.shape, want.shape);
  const float range = *std::max_element(want.values.begin(), want.values.end()) -
                      *std::min_element(want.values.begin(), want.values.end());
  for (std::size_t i = 0; i < got.values.size(); ++i) ASSERT_NEAR(got.values[i], want.values[i], 1e-3f * range);
  fs::remove(out);
  fs::remove(err);
}

// The raw logits whatever the model's class names: 13 per point for the S3DIS fixture.
TEST(ClassifyRawBlock, GivesEveryLogitOfAModelWithAnotherClassList) {
  const fs::path out =
      fs::temp_directory_path() / ("sarmap_logits_s3dis_" + std::to_string(::getpid()) + ".npy");
  const fs::path err = out.string() + ".err";
  ASSERT_EQ(run_classify_raw("--raw-block " + kDgcnnDataDir + "block_c6_n1024.npy --model " + kDgcnnDataDir +
                    "model_s3dis13.safetensors --logits " + out.string(),
                err),
            0);
  const NpyArray got = read_npy_f32(out);
  EXPECT_EQ(got.shape, (std::vector<std::size_t>{1024, 13}));
  EXPECT_TRUE(std::all_of(got.values.begin(), got.values.end(), [](float v) { return std::isfinite(v); }));
  fs::remove(out);
  fs::remove(err);
}

TEST(ClassifyRawBlock, RefusesABlockOfTheWrongWidth) {
  const fs::path out = fs::temp_directory_path() / ("sarmap_logits_bad_" + std::to_string(::getpid()) + ".npy");
  const fs::path err = out.string() + ".err";
  EXPECT_NE(run_classify_raw("--raw-block " + kDgcnnDataDir + "block_c6_n1024.npy --model " + kDgcnnDataDir + "model_c9.safetensors --logits " +
                    out.string(),
                err),
            0);
  EXPECT_FALSE(fs::exists(out));
  std::ifstream in(err);
  const std::string message((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(message.find("expects (N, 9)"), std::string::npos) << message;
  fs::remove(err);
}

}  // namespace
}  // namespace sarmap
