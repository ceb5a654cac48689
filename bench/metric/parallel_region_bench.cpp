// What a short parallel region costs on this machine beyond its work, after
// a serial stretch of a given length: the integrator's per-scan path runs
// four regions per scan (pass 1's chunks and rays, the walk, pass 4), each a
// few hundred microseconds, with serial merges between them. oneTBB's
// workers spin for a while after a region ends and then sleep; a region
// that starts after they slept waits for one to wake, which on a virtual
// machine can cost as much as the region's work. BM_SarmapPasses says how
// well each pass scales; this says how much of that the platform allows,
// and (wake_us > 0) how much of it wake_workers() saves when called that
// many microseconds before the region, as the Mapper calls it before the
// classify stage that precedes its metric stage.
#include <benchmark/benchmark.h>

#include <chrono>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "engine/core/wake_workers.hpp"

namespace {

using Clock = std::chrono::steady_clock;

// Busy for `us` microseconds: the serial stretch, or one task's work,
// without sleeping (a sleep would hand the core to the worker instead).
void busy_for(double us) {
  const Clock::time_point start = Clock::now();
  while (std::chrono::duration<double, std::micro>(Clock::now() - start).count() < us) {
  }
}

// Args: the serial stretch before each region (us), threads, and how long
// before the region's start wake_workers() is called (us; 0: not called).
// Each region is
// two tasks of 20 us, so it takes 20 us when both threads run at once and
// 40 us on one; the reported time is the region's alone (manual time).
void BM_ParallelRegionAfterGap(benchmark::State& state) {
  const double gap_us = static_cast<double>(state.range(0));
  const auto threads = static_cast<std::size_t>(state.range(1));
  const double wake_us = static_cast<double>(state.range(2));
  constexpr double kTaskUs = 20;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  double region_us = 0;
  for (auto _ : state) {
    if (wake_us > 0) {
      busy_for(gap_us - wake_us);
      sarmap::wake_workers();
      busy_for(wake_us);
    } else {
      busy_for(gap_us);
    }
    const Clock::time_point start = Clock::now();
    tbb::parallel_for(0, 2, [&](int) { busy_for(kTaskUs); }, tbb::simple_partitioner());
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    region_us += seconds * 1e6;
    state.SetIterationTime(seconds);
  }
  // Beyond the region's work split over the threads (20 us at 2, 40 at 1).
  const double ideal_us = 2 * kTaskUs / static_cast<double>(threads);
  state.counters["excess_us"] =
      benchmark::Counter(region_us - ideal_us * static_cast<double>(state.iterations()),
                         benchmark::Counter::kAvgIterations);
}

BENCHMARK(BM_ParallelRegionAfterGap)->ArgNames({"gap_us", "threads", "wake_us"})
    ->Args({0, 1, 0})->Args({0, 2, 0})->Args({100, 2, 0})->Args({300, 2, 0})->Args({1000, 2, 0})
    ->Args({3000, 2, 0})->Args({1000, 2, 10})->Args({1000, 2, 25})->Args({1000, 2, 50})->Args({1000, 2, 100})->Args({1000, 2, 250})
    ->UseManualTime()->Unit(benchmark::kMicrosecond)->MinTime(0.5);

}  // namespace
