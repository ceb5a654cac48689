// Tests engine/semantic/dgcnn/dgcnn_model.hpp end to end against the golden logits
// of tools/python/dgcnn_reference.py (float64 PyTorch, random weights with BN
// statistics measured on a block): C = 6 and C = 9, N = 1024 and 4096, every
// instruction set, and identical results with 1 and 2 threads.
#include "engine/semantic/dgcnn/dgcnn_model.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/npy.hpp"
#include "tests/semantic/dgcnn_test_data.hpp"

namespace sarmap {
namespace {

using testing::kDgcnnDataDir;

struct Golden {
  int channels;
  int points;
};

std::vector<float> run(const DgcnnModel& model, const NpyArray& block) {
  DgcnnWorkspace ws;
  std::vector<float> logits(block.shape[0] * model.classes());
  model.forward(block.values.data(), block.shape[0], logits.data(), ws);
  return logits;
}

class DgcnnGolden : public ::testing::TestWithParam<Golden> {};

TEST_P(DgcnnGolden, MatchesReferenceLogits) {
  const Golden g = GetParam();
  const std::string tag = "c" + std::to_string(g.channels) + "_n" + std::to_string(g.points);
  const NpyArray block = read_npy_f32(kDgcnnDataDir + "block_" + tag + ".npy");
  const NpyArray expected = read_npy_f32(kDgcnnDataDir + "logits_" + tag + ".npy");
  ASSERT_EQ(block.shape, (std::vector<std::size_t>{std::size_t(g.points), std::size_t(g.channels)}));
  const float range = *std::max_element(expected.values.begin(), expected.values.end()) -
                      *std::min_element(expected.values.begin(), expected.values.end());
  for (kernels::SimdLevel level : {kernels::SimdLevel::Sse42, kernels::SimdLevel::Avx2, kernels::SimdLevel::Avx512}) {
    if (!kernels::simd_level_supported(level)) continue;
    const DgcnnModel model = DgcnnModel::load(kDgcnnDataDir + "model_c" + std::to_string(g.channels) + ".safetensors", level);
    ASSERT_EQ(model.channels(), std::size_t(g.channels));
    const std::size_t classes = model.classes();
    ASSERT_EQ(expected.shape, (std::vector<std::size_t>{std::size_t(g.points), classes}));
    const std::vector<float> got = run(model, block);
    double max_diff = 0.0;
    std::size_t same_argmax = 0;
    for (std::size_t i = 0; i < std::size_t(g.points); ++i) {
      const float* a = &got[i * classes];
      const float* b = &expected.values[i * classes];
      for (std::size_t c = 0; c < classes; ++c) max_diff = std::max(max_diff, double(std::abs(a[c] - b[c])));
      same_argmax += std::max_element(a, a + classes) - a == std::max_element(b, b + classes) - b;
    }
    EXPECT_LE(max_diff, 1e-3 * range) << kernels::to_string(level) << " " << tag;
    EXPECT_GE(double(same_argmax), 0.999 * g.points) << kernels::to_string(level) << " " << tag;
  }
}

INSTANTIATE_TEST_SUITE_P(Fixtures, DgcnnGolden,
                         ::testing::Values(Golden{6, 1024}, Golden{6, 4096}, Golden{9, 1024}, Golden{9, 4096}),
                         [](const auto& info) {
                           return "C" + std::to_string(info.param.channels) + "N" + std::to_string(info.param.points);
                         });

TEST(DgcnnModel, SameLogitsWithOneAndTwoThreads) {
  const DgcnnModel model = DgcnnModel::load(kDgcnnDataDir + "model_c6.safetensors");
  const NpyArray block = read_npy_f32(kDgcnnDataDir + "block_c6_n4096.npy");
  std::vector<float> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = run(model, block);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = run(model, block);
  }
  EXPECT_EQ(one, two);
}

TEST(DgcnnModel, FewerPointsThanKStillRuns) {
  const DgcnnModel model = DgcnnModel::load(kDgcnnDataDir + "model_c6.safetensors");
  const NpyArray block = read_npy_f32(kDgcnnDataDir + "block_c6_n1024.npy");
  DgcnnWorkspace ws;
  std::vector<float> logits(5 * model.classes());
  model.forward(block.values.data(), 5, logits.data(), ws);
  for (float v : logits) EXPECT_TRUE(std::isfinite(v));
}

// Every buffer's address, to see that a second block of the same size
// allocated nothing (a grow-only buffer that grew would have moved).
std::vector<const void*> buffer_addresses(const DgcnnWorkspace& ws) {
  return {ws.knn.panels.data(), ws.knn.norms.data(), ws.knn.centre.data(), ws.neighbours.data(),
          ws.edge_terms.data(), ws.local.data(),     ws.global.data(),      ws.head_bias.data(),
          ws.head1.data(),      ws.head2.data()};
}

TEST(DgcnnModel, BlocksAfterTheFirstAllocateNothing) {
  const DgcnnModel model = DgcnnModel::load(kDgcnnDataDir + "model_c6.safetensors");
  const NpyArray big = read_npy_f32(kDgcnnDataDir + "block_c6_n4096.npy");
  const NpyArray small = read_npy_f32(kDgcnnDataDir + "block_c6_n1024.npy");
  DgcnnWorkspace ws;
  std::vector<float> logits(big.shape[0] * model.classes());
  model.forward(big.values.data(), big.shape[0], logits.data(), ws);
  const std::size_t bytes = ws.bytes();
  const auto addresses = buffer_addresses(ws);
  for (const void* a : addresses) EXPECT_NE(a, nullptr);
  // A 4096-point block's working set: a few MB, not the N x N distances (64 MB).
  EXPECT_GT(bytes, std::size_t{1} << 20);
  EXPECT_LT(bytes, std::size_t{32} << 20);
  model.forward(small.values.data(), small.shape[0], logits.data(), ws);
  model.forward(big.values.data(), big.shape[0], logits.data(), ws);
  EXPECT_EQ(ws.bytes(), bytes);
  EXPECT_EQ(buffer_addresses(ws), addresses);
}

TEST(DgcnnModel, RejectsNonFiniteInput) {
  const DgcnnModel model = DgcnnModel::load(kDgcnnDataDir + "model_c6.safetensors");
  std::vector<float> block(64 * 6, 0.5f);
  block[10 * 6 + 2] = std::nanf("");
  std::vector<float> logits(64 * model.classes());
  DgcnnWorkspace ws;
  EXPECT_THROW(model.forward(block.data(), 64, logits.data(), ws), Error);
}

}  // namespace
}  // namespace sarmap
