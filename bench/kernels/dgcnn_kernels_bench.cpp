// The DGCNN kernels one at a time on a 4096-point block's shapes, at each
// instruction set and at 1 and 2 threads, with GFLOP/s: kNN in 3-D and 64-D
// (in input order and in the network's spatial order),
// the fused two-convolution EdgeConv, the conv6 column-max GEMM and the
// 512-wide head GEMM.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "kernels/edge_conv.hpp"
#include "kernels/gemm.hpp"
#include "kernels/knn.hpp"
#include "kernels/spatial_order.hpp"

namespace {

using sarmap::kernels::SimdLevel;
constexpr std::size_t kPoints = 4096, kK = 20;

std::vector<float> random_floats(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> d(0.0f, 1.0f);
  std::vector<float> v(n);
  for (float& x : v) x = d(rng);
  return v;
}

bool setup(benchmark::State& state, SimdLevel level) {
  if (!sarmap::kernels::simd_level_supported(level)) {
    state.SkipWithError("not supported by this CPU");
    return false;
  }
  return true;
}

void rate(benchmark::State& state, double flops) {
  state.counters["GFLOP/s"] = benchmark::Counter(flops * state.iterations() / 1e9, benchmark::Counter::kIsRate);
}

void BM_Knn(benchmark::State& state, SimdLevel level) {
  if (!setup(state, level)) return;
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(1));
  const std::size_t dim = state.range(0);
  const auto p = random_floats(kPoints * dim, 1);
  std::vector<std::uint32_t> idx(kPoints * kK);
  sarmap::kernels::KnnWorkspace ws;
  for (auto _ : state) sarmap::kernels::knn(p.data(), dim, kPoints, dim, kK, level, ws, idx.data());
  rate(state, 2.0 * kPoints * kPoints * dim);
}

// kNN in the order the network uses: the points sorted along a Hilbert curve
// of their xyz first (spatial_order(), timed with it). In 3-D the points are
// the xyz themselves; in 64-D they are features that vary smoothly with
// position (tanh of a random linear map of xyz), as DGCNN's later layers'
// features do, so that nearby points in space are mostly near in features.
void BM_KnnSpatialOrder(benchmark::State& state, SimdLevel level) {
  if (!setup(state, level)) return;
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(1));
  const std::size_t dim = state.range(0);
  const auto xyz = random_floats(kPoints * 3, 1);
  std::vector<float> p = xyz;
  if (dim != 3) {
    const auto w = random_floats(dim * 3, 2);
    p.resize(kPoints * dim);
    for (std::size_t i = 0; i < kPoints; ++i) {
      for (std::size_t c = 0; c < dim; ++c) {
        p[i * dim + c] = std::tanh(w[c * 3] * xyz[i * 3] + w[c * 3 + 1] * xyz[i * 3 + 1] + w[c * 3 + 2] * xyz[i * 3 + 2]);
      }
    }
  }
  std::vector<std::uint32_t> idx(kPoints * kK), order(kPoints);
  sarmap::kernels::KnnWorkspace ws;
  sarmap::kernels::AlignedBuffer<std::uint64_t> keys;
  for (auto _ : state) {
    sarmap::kernels::spatial_order(xyz.data(), 3, kPoints, keys, order.data());
    sarmap::kernels::knn(p.data(), dim, kPoints, dim, kK, level, ws, idx.data(), order.data());
  }
  rate(state, 2.0 * kPoints * kPoints * dim);
}

void BM_EdgeConv(benchmark::State& state, SimdLevel level) {
  if (!setup(state, level)) return;
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  const std::size_t h = 64;
  const auto ab = random_floats(kPoints * 2 * h, 2), w = random_floats(h * h, 3);
  std::vector<std::uint32_t> idx(kPoints * kK);
  std::mt19937 rng(4);
  for (auto& i : idx) i = rng() % kPoints;
  const sarmap::kernels::PackedMatrix packed(w.data(), nullptr, h, h, level);
  std::vector<float> out(kPoints * h);
  for (auto _ : state) {
    sarmap::kernels::edge_conv_max(ab.data(), ab.data() + h, 2 * h, kPoints, h, idx.data(), kK, 0.2f, packed, 0.2f,
                                   out.data(), h);
  }
  rate(state, kPoints * kK * (2.0 * h * h + h));
}

void BM_GemmColumnMax(benchmark::State& state, SimdLevel level) {
  if (!setup(state, level)) return;
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  const std::size_t in = 192, out = 1024;
  const auto x = random_floats(kPoints * in, 5), w = random_floats(out * in, 6);
  const sarmap::kernels::PackedMatrix packed(w.data(), nullptr, out, in, level);
  std::vector<float> colmax(out);
  for (auto _ : state) sarmap::kernels::gemm_column_max(x.data(), in, kPoints, packed, colmax.data());
  rate(state, 2.0 * kPoints * in * out);
}

void BM_Gemm(benchmark::State& state, SimdLevel level) {
  if (!setup(state, level)) return;
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  const std::size_t in = 512, out = 256;
  const auto x = random_floats(kPoints * in, 7), w = random_floats(out * in, 8);
  const sarmap::kernels::PackedMatrix packed(w.data(), nullptr, out, in, level);
  std::vector<float> y(kPoints * out);
  for (auto _ : state) sarmap::kernels::gemm_bias_act(x.data(), in, kPoints, packed, 0.2f, y.data(), out);
  rate(state, 2.0 * kPoints * in * out);
}

#define SARMAP_LEVELS(fn, args)                                               \
  BENCHMARK_CAPTURE(fn, sse4_2, SimdLevel::Sse42) args->Unit(benchmark::kMillisecond)->UseRealTime(); \
  BENCHMARK_CAPTURE(fn, avx2, SimdLevel::Avx2) args->Unit(benchmark::kMillisecond)->UseRealTime();    \
  BENCHMARK_CAPTURE(fn, avx512, SimdLevel::Avx512) args->Unit(benchmark::kMillisecond)->UseRealTime();

SARMAP_LEVELS(BM_Knn, ->ArgNames({"dim", "threads"})->Args({3, 1})->Args({3, 2})->Args({64, 1})->Args({64, 2}))
SARMAP_LEVELS(BM_KnnSpatialOrder, ->ArgNames({"dim", "threads"})->Args({3, 1})->Args({3, 2})->Args({64, 1})->Args({64, 2}))
SARMAP_LEVELS(BM_EdgeConv, ->ArgName("threads")->Arg(1)->Arg(2))
SARMAP_LEVELS(BM_GemmColumnMax, ->ArgName("threads")->Arg(1)->Arg(2))
SARMAP_LEVELS(BM_Gemm, ->ArgName("threads")->Arg(1)->Arg(2))

}  // namespace
