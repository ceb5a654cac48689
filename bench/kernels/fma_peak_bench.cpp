// This machine's FP32 peak: independent FMA chains in registers, AVX2 and
// AVX-512, so the kernels' GFLOP/s can be read as a share of what the core
// can do, and the dispatch preference is chosen by measurement.
#include <benchmark/benchmark.h>
#include <immintrin.h>

#include "kernels/simd_level.hpp"

namespace {

constexpr int kIterations = 1 << 16;

__attribute__((target("avx2,fma"))) float fma_loop_avx2() {
  __m256 a[10];
  for (int i = 0; i < 10; ++i) a[i] = _mm256_set1_ps(1.0f + 0.001f * i);
  const __m256 m = _mm256_set1_ps(0.999999f), c = _mm256_set1_ps(1e-7f);
  for (int it = 0; it < kIterations; ++it) {
    for (int i = 0; i < 10; ++i) {
      a[i] = _mm256_fmadd_ps(a[i], m, c);
      __asm__ volatile("" : "+v"(a[i]));  // keeps the chain from being folded away
    }
  }
  __m256 s = a[0];
  for (int i = 1; i < 10; ++i) s = _mm256_add_ps(s, a[i]);
  return _mm256_cvtss_f32(s);
}

__attribute__((target("avx512f"))) float fma_loop_avx512() {
  __m512 a[10];
  for (int i = 0; i < 10; ++i) a[i] = _mm512_set1_ps(1.0f + 0.001f * i);
  const __m512 m = _mm512_set1_ps(0.999999f), c = _mm512_set1_ps(1e-7f);
  for (int it = 0; it < kIterations; ++it) {
    for (int i = 0; i < 10; ++i) {
      a[i] = _mm512_fmadd_ps(a[i], m, c);
      __asm__ volatile("" : "+v"(a[i]));
    }
  }
  return _mm512_reduce_add_ps(a[0]) + _mm512_reduce_add_ps(a[9]);
}

void BM_FmaPeak(benchmark::State& state, sarmap::kernels::SimdLevel level) {
  if (!sarmap::kernels::simd_level_supported(level)) {
    state.SkipWithError("not supported by this CPU");
    return;
  }
  const int lanes = sarmap::kernels::simd_lanes(level);
  for (auto _ : state) {
    benchmark::DoNotOptimize(level == sarmap::kernels::SimdLevel::Avx512 ? fma_loop_avx512() : fma_loop_avx2());
  }
  const double flops = 2.0 * lanes * 10.0 * kIterations;
  state.counters["GFLOP/s"] = benchmark::Counter(flops * state.iterations() / 1e9, benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(BM_FmaPeak, avx2, sarmap::kernels::SimdLevel::Avx2);
BENCHMARK_CAPTURE(BM_FmaPeak, avx512, sarmap::kernels::SimdLevel::Avx512);

}  // namespace
