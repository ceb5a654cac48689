// Where a scan's integration time goes, one scan at a time as Mapper feeds
// the integrator: the default arena's frames through ScanRays::compute
// (passes 1 and 2: the end voxels, then their rays walked, the walks
// starting while pass 1's serial merge goes on) and ScanUpdate::apply
// (passes 3 and 4: the serial merge and block creation, then the parallel
// block updates), each half timed on its own and reported as milliseconds
// summed over the frames. Run at 1 and 2 threads, the ratio per half says
// how much the second thread speeds it up, and what holds the per-scan path
// back against integrate_sequence(), which overlaps the two halves of
// consecutive scans to hide their serial parts.
#include <benchmark/benchmark.h>

#include <chrono>
#include <vector>

#include <tbb/global_control.h>

#include "bench/metric/fastest_run.hpp"
#include "bench/metric/sequence_fixture.hpp"
#include "engine/metric/metric_map.hpp"
#include "engine/metric/scan_rays.hpp"
#include "engine/metric/scan_update.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Args: resolution in mm, image width, threads.
void BM_SarmapPasses(benchmark::State& state) {
  const double res = state.range(0) / 1000.0;
  const int width = static_cast<int>(state.range(1));
  const auto threads = static_cast<std::size_t>(state.range(2));
  const auto& scans = sarmap::bench::default_arena_sequence(width);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  const sarmap::metric::IntegratorSettings settings;
  sarmap::metric::ScanRays rays;
  sarmap::metric::ScanUpdate update;
  double trace_ms = 0, update_ms = 0;
  std::size_t visits = 0;
  for (auto _ : state) {
    sarmap::metric::MetricMap map(sarmap::metric::settings_at_resolution(res));
    sarmap::metric::IntegrationStats stats;
    for (const sarmap::Scan& s : scans) {
      auto start = Clock::now();
      rays.compute(settings, map.resolution(), s.points, s.origin, stats);
      trace_ms += ms_since(start);
      start = Clock::now();
      update.apply(map, rays, stats);
      update_ms += ms_since(start);
    }
    visits = stats.voxel_visits;
    benchmark::DoNotOptimize(map.counts().known);
  }
  // Per iteration (every iteration maps the same frames into a fresh map).
  using C = benchmark::Counter;
  state.counters["trace_ms"] = C(trace_ms, C::kAvgIterations);
  state.counters["update_ms"] = C(update_ms, C::kAvgIterations);
  state.counters["voxel_visits"] = static_cast<double>(visits);
}

// As BM_Sarmap: three runs, the fastest as "_min" (of each counter too).
BENCHMARK(BM_SarmapPasses)->ArgNames({"res_mm", "width", "threads"})
    ->Args({50, 320, 1})->Args({50, 320, 2})->Args({25, 320, 1})->Args({25, 320, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0)
    ->Repetitions(3)->ComputeStatistics("min", sarmap::bench::fastest);

}  // namespace
