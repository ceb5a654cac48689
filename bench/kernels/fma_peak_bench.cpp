// This machine's FP32 peak: independent FMA chains in registers, AVX2 and
// AVX-512, so the kernels' GFLOP/s can be read as a share of what the core
// can do, and the dispatch preference is chosen by measurement.
#include <benchmark/benchmark.h>
#include <immintrin.h>

#include "kernels/simd_level.hpp"

namespace {

constexpr int kIterations = 1 << 16;
constexpr int kChains = 12;  // latency 4 x 2 FMA ports = 8 in flight; 12 leaves slack

// Twelve named accumulators and one empty asm that claims to modify all of
// them: the chains stay in registers (an array, even fully unrolled, was
// spilled to the stack, which measured store-forwarding latency instead of
// the FMA units) and the compiler cannot fold the loop away.
#define SARMAP_FMA_CHAINS(FMA, VEC, SET1, ADD, SUM)                                             \
  VEC a0 = SET1(1.000f), a1 = SET1(1.001f), a2 = SET1(1.002f), a3 = SET1(1.003f);               \
  VEC a4 = SET1(1.004f), a5 = SET1(1.005f), a6 = SET1(1.006f), a7 = SET1(1.007f);               \
  VEC a8 = SET1(1.008f), a9 = SET1(1.009f), a10 = SET1(1.010f), a11 = SET1(1.011f);             \
  const VEC m = SET1(0.999999f), c = SET1(1e-7f);                                               \
  for (int it = 0; it < kIterations; ++it) {                                                    \
    a0 = FMA(a0, m, c); a1 = FMA(a1, m, c); a2 = FMA(a2, m, c); a3 = FMA(a3, m, c);             \
    a4 = FMA(a4, m, c); a5 = FMA(a5, m, c); a6 = FMA(a6, m, c); a7 = FMA(a7, m, c);             \
    a8 = FMA(a8, m, c); a9 = FMA(a9, m, c); a10 = FMA(a10, m, c); a11 = FMA(a11, m, c);         \
    __asm__ volatile("" : "+v"(a0), "+v"(a1), "+v"(a2), "+v"(a3), "+v"(a4), "+v"(a5), "+v"(a6), \
                     "+v"(a7), "+v"(a8), "+v"(a9), "+v"(a10), "+v"(a11));                       \
  }                                                                                             \
  const VEC s = ADD(ADD(ADD(ADD(a0, a1), ADD(a2, a3)), ADD(ADD(a4, a5), ADD(a6, a7))),          \
                    ADD(ADD(a8, a9), ADD(a10, a11)));                                           \
  return SUM(s)

__attribute__((target("avx2,fma"))) float fma_loop_avx2() {
  SARMAP_FMA_CHAINS(_mm256_fmadd_ps, __m256, _mm256_set1_ps, _mm256_add_ps, _mm256_cvtss_f32);
}

__attribute__((target("avx512f"))) float fma_loop_avx512() {
  SARMAP_FMA_CHAINS(_mm512_fmadd_ps, __m512, _mm512_set1_ps, _mm512_add_ps, _mm512_reduce_add_ps);
}

#undef SARMAP_FMA_CHAINS

void BM_FmaPeak(benchmark::State& state, sarmap::kernels::SimdLevel level) {
  if (!sarmap::kernels::simd_level_supported(level)) {
    state.SkipWithError("not supported by this CPU");
    return;
  }
  const int lanes = sarmap::kernels::simd_lanes(level);
  for (auto _ : state) {
    benchmark::DoNotOptimize(level == sarmap::kernels::SimdLevel::Avx512 ? fma_loop_avx512() : fma_loop_avx2());
  }
  const double flops = 2.0 * lanes * kChains * static_cast<double>(kIterations);
  state.counters["GFLOP/s"] = benchmark::Counter(flops * state.iterations() / 1e9, benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(BM_FmaPeak, avx2, sarmap::kernels::SimdLevel::Avx2)->Threads(1)->Threads(2)->UseRealTime();
BENCHMARK_CAPTURE(BM_FmaPeak, avx512, sarmap::kernels::SimdLevel::Avx512)->Threads(1)->Threads(2)->UseRealTime();

}  // namespace
