// The whole DGCNN on one 4096-point block (full size: emb 1024, head 512/256)
// at 1 and 2 threads and each instruction set, with GFLOP/s on the rewritten
// FLOP count and the time of each stage. The weights are random (speed does
// not depend on their values); the block is the golden fixture's. With
// SARMAP_DGCNN_MODEL set, that .safetensors model is used instead (the
// PyTorch peer script passes the model it times).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "engine/io/npy.hpp"
#include "engine/semantic/dgcnn/dgcnn_model.hpp"

namespace {

using sarmap::kernels::SimdLevel;

sarmap::ConvLayer random_layer(const std::string& name, std::size_t out, std::size_t in, bool bn, std::mt19937& rng) {
  std::normal_distribution<float> d(0.0f, 1.0f);
  sarmap::ConvLayer l;
  l.name = name;
  l.out = out;
  l.in = in;
  l.weight.resize(out * in);
  for (float& w : l.weight) w = d(rng) / std::sqrt(static_cast<float>(in));
  l.has_bn = bn;
  if (bn) {
    l.bn_gamma.assign(out, 1.0f);
    l.bn_beta.resize(out);
    for (float& b : l.bn_beta) b = 0.1f * d(rng);
    l.bn_mean.assign(out, 0.0f);
    l.bn_var.assign(out, 1.0f);
  }
  return l;
}

sarmap::DgcnnModel make_model(SimdLevel level, std::size_t channels) {
  if (const char* path = std::getenv("SARMAP_DGCNN_MODEL")) return sarmap::DgcnnModel::load(path, level);
  std::mt19937 rng(1);
  sarmap::DgcnnWeights w;
  const std::size_t dims[9][2] = {{64, 2 * channels}, {64, 64}, {64, 128}, {64, 64}, {64, 128},
                                  {1024, 192},        {512, 1216}, {256, 512}, {4, 256}};
  for (int i = 0; i < 9; ++i) w.conv[i] = random_layer("conv" + std::to_string(i + 1), dims[i][0], dims[i][1], i < 8, rng);
  return sarmap::DgcnnModel(w, sarmap::DgcnnMetadata{}, level);
}

void BM_DgcnnBlock(benchmark::State& state, SimdLevel level) {
  if (!sarmap::kernels::simd_level_supported(level)) {
    state.SkipWithError("not supported by this CPU");
    return;
  }
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  const char* block_path = std::getenv("SARMAP_DGCNN_BLOCK");
  const sarmap::NpyArray block = sarmap::read_npy_f32(
      block_path ? std::string(block_path) : std::string(SARMAP_SOURCE_DIR) + "/tests/data/dgcnn/block_c6_n4096.npy");
  const sarmap::DgcnnModel model = make_model(level, block.shape[1]);
  const std::size_t n = block.shape[0];
  std::vector<float> logits(n * model.classes());
  sarmap::DgcnnWorkspace ws;
  sarmap::DgcnnStageTimes t, sum;
  model.forward(block.values.data(), n, logits.data(), ws);  // warm-up: buffers reach their size
  for (auto _ : state) {
    model.forward(block.values.data(), n, logits.data(), ws, &t);
    for (int e = 0; e < 3; ++e) {
      sum.knn[e] += t.knn[e];
      sum.edge_conv[e] += t.edge_conv[e];
    }
    sum.global += t.global;
    sum.head += t.head;
  }
  const double it = static_cast<double>(state.iterations());
  state.counters["GFLOP/s"] = benchmark::Counter(model.flops(n) * it / 1e9, benchmark::Counter::kIsRate);
  state.counters["GFLOP"] = model.flops(n) / 1e9;
  for (int e = 0; e < 3; ++e) {
    state.counters["knn" + std::to_string(e + 1) + "_ms"] = 1e3 * sum.knn[e] / it;
    state.counters["edge" + std::to_string(e + 1) + "_ms"] = 1e3 * sum.edge_conv[e] / it;
  }
  state.counters["global_ms"] = 1e3 * sum.global / it;
  state.counters["head_ms"] = 1e3 * sum.head / it;
  state.counters["workspace_MiB"] = static_cast<double>(ws.bytes()) / (1024.0 * 1024.0);
}

BENCHMARK_CAPTURE(BM_DgcnnBlock, sse4_2, SimdLevel::Sse42)->ArgName("threads")->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DgcnnBlock, avx2, SimdLevel::Avx2)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DgcnnBlock, avx512, SimdLevel::Avx512)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
