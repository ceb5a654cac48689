// sarmap's metric map against OctoMap (Debian's liboctomap) in one binary, on
// the same simulated sequence: OctoMap's insertPointCloud(..., discretize=true)
// versus RayIntegrator at 0.05 m and 0.025 m, sarmap at 1 and 2 threads, fed
// one frame at a time (also with the caches evicted between frames, as
// between a pipeline's metric stages, or with a pause alone between them,
// busy or asleep)
// and as a sequence (integrate_sequence),
// and both at 320 x 240 and 640 x 480; the building arena (52 x 15 m) at
// 640 x 480 for a larger map. Each iteration maps all frames into a fresh
// map; each case runs three times (the building arena's OctoMap once) and
// reports the fastest too.
// Memory, after the last frame: OctoMap's memoryUsage(); sarmap's map as it
// counts its own allocations (MetricMap::memory_bytes: block records and
// their hash table, log-odds slabs, evidence rows, each also on its own),
// and apart from it the integrator's scratch
// (RayIntegrator::scratch_bytes), which a map does not keep. PERF.md states
// what each counts.
#include <benchmark/benchmark.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <tbb/global_control.h>

#include "bench/metric/fastest_run.hpp"
#include "bench/metric/sequence_fixture.hpp"
#include "engine/core/wake_workers.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "kernels/simd_level.hpp"

namespace {

using sarmap::Scan;

struct OctoFrame {
  octomap::Pointcloud cloud;
  octomap::point3d origin;
};

using Sequence = const std::vector<Scan>& (*)(int width);

const std::vector<OctoFrame>& octomap_frames(Sequence sequence, int width) {
  static std::map<std::pair<Sequence, int>, std::vector<OctoFrame>> cache;
  auto& frames = cache[{sequence, width}];
  if (!frames.empty()) return frames;
  for (const Scan& s : sequence(width)) {
    OctoFrame f;
    f.cloud.reserve(s.points.size());
    for (std::size_t i = 0; i < s.points.size(); ++i) f.cloud.push_back(s.points.x()[i], s.points.y()[i], s.points.z()[i]);
    f.origin = octomap::point3d(static_cast<float>(s.origin.x()), static_cast<float>(s.origin.y()),
                                static_cast<float>(s.origin.z()));
    frames.push_back(std::move(f));
  }
  return frames;
}

// Voxels at the finest resolution that a tree knows (pruned leaves expanded).
std::size_t octomap_known_voxels(const octomap::OcTree& tree) {
  std::size_t n = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const auto edge = static_cast<std::size_t>(std::lround(it.getSize() / tree.getResolution()));
    n += edge * edge * edge;
  }
  return n;
}

// Args: resolution in mm, image width.
template <Sequence sequence = sarmap::bench::default_arena_sequence>
void BM_OctoMap(benchmark::State& state) {
  const double res = state.range(0) / 1000.0;
  const int width = static_cast<int>(state.range(1));
  const auto& frames = octomap_frames(sequence, width);
  const std::size_t points = sarmap::bench::total_points(sequence(width));
  std::size_t known = 0, bytes = 0;
  for (auto _ : state) {
    octomap::OcTree tree(res);
    for (const OctoFrame& f : frames) tree.insertPointCloud(f.cloud, f.origin, -1.0, false, true);
    state.PauseTiming();
    known = octomap_known_voxels(tree);
    bytes = tree.memoryUsage();
    state.ResumeTiming();
  }
  state.counters["points_per_s"] = benchmark::Counter(static_cast<double>(points), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["known_voxels"] = static_cast<double>(known);
  state.counters["bytes_per_known_voxel"] = static_cast<double>(bytes) / static_cast<double>(known);
  state.counters["memory_MB"] = static_cast<double>(bytes) / 1e6;
}

// How sarmap is given the frames: one integrate() call per frame, or the
// whole sequence to integrate_sequence(), which traces frame k's rays while
// frame k - 1 is written into the map (as the Mapper's stream does), or one
// call per frame with the caches evicted between frames, untimed: inside
// `sarmap run` and the Mapper the other stages run between two scans'
// metric stages and leave their own data in the caches (and the workers
// asleep, which the Mapper wakes ahead of the stage, as this does), or one
// call per frame with the calling thread busy between frames, untimed, on
// work that touches no memory: the other stages' time without their data,
// to tell apart what a pause alone costs the next scan (its workers asleep,
// its predictors and caches left to whatever else the cores ran), or one
// call per frame with the calling thread asleep between frames: a front end
// that maps each scan as its sensor delivers it and waits idle for the next,
// its cores free to idle too.
enum class Feed { PerScan, Sequence, PerScanCachesEvicted, PerScanPaused, PerScanIdle };

// Writes one word in every cache line of words: what a stage that touches
// that much memory leaves of the caches' earlier contents.
void evict_caches(std::vector<std::uint64_t>& words) {
  for (std::size_t w = 0; w < words.size(); w += 8) words[w] += 1;
  benchmark::DoNotOptimize(words.data());
}

// Spins for `pause` on arithmetic alone, touching no memory (a sleep would
// let the core idle, which a busy pipeline does not). Not the clock-only
// spin of parallel_region_bench.cpp's busy_for: between scans that one cost
// the next scan far more than the arithmetic does at one thread on one kind
// of machine, and more than the run's real stages (docs/perf-history.md): it
// could overstate a pause.
void busy_pause(std::chrono::microseconds pause) {
  const auto until = std::chrono::steady_clock::now() + pause;
  std::uint64_t x = 1;
  while (std::chrono::steady_clock::now() < until) {
    for (int i = 0; i < 64; ++i) x = x * 6364136223846793005ULL + 1442695040888963407ULL;
  }
  benchmark::DoNotOptimize(x);
}

// Args: resolution in mm, image width, threads (and for
// PerScanCachesEvicted the MiB written between frames, for PerScanPaused and
// PerScanIdle the microseconds of the pause).
template <Feed feed, Sequence sequence = sarmap::bench::default_arena_sequence>
void BM_Sarmap(benchmark::State& state) {
  const double res = state.range(0) / 1000.0;
  const int width = static_cast<int>(state.range(1));
  const auto threads = static_cast<std::size_t>(state.range(2));
  const auto& scans = sequence(width);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  sarmap::metric::IntegrationStats stats;
  std::size_t known = 0, bytes = 0, scratch = 0;
  sarmap::metric::SemanticBlocks::Memory parts;
  sarmap::metric::RayIntegrator integrator;
  std::vector<std::uint64_t> evicting;
  if constexpr (feed == Feed::PerScanCachesEvicted) {
    evicting.assign(static_cast<std::size_t>(state.range(3)) << 17, 0);  // MiB in 8-byte words
  }
  for (auto _ : state) {
    sarmap::metric::MetricMap map(sarmap::metric::settings_at_resolution(res));
    stats = {};
    if constexpr (feed == Feed::PerScan) {
      for (const Scan& s : scans) stats += integrator.integrate(map, s.points, s.origin);
    } else if constexpr (feed != Feed::Sequence) {
      for (const Scan& s : scans) {
        stats += integrator.integrate(map, s.points, s.origin);
        state.PauseTiming();
        if constexpr (feed == Feed::PerScanCachesEvicted) {
          evict_caches(evicting);
        } else if constexpr (feed == Feed::PerScanPaused) {
          busy_pause(std::chrono::microseconds(state.range(3)));
        } else {
          std::this_thread::sleep_for(std::chrono::microseconds(state.range(3)));
        }
        sarmap::wake_workers();  // as the Mapper does before its metric stage
        state.ResumeTiming();
      }
    } else {
      for (const auto& one : integrator.integrate_sequence(map, scans)) stats += one;
    }
    state.PauseTiming();
    known = map.counts().known;
    bytes = map.memory_bytes();
    parts = map.blocks().memory();
    scratch = integrator.scratch_bytes();
    state.ResumeTiming();
  }
  using C = benchmark::Counter;
  state.counters["points_per_s"] = C(static_cast<double>(stats.points_in), C::kIsIterationInvariantRate);
  state.counters["rays_per_s"] = C(static_cast<double>(stats.rays), C::kIsIterationInvariantRate);
  state.counters["voxel_visits_per_s"] = C(static_cast<double>(stats.voxel_visits), C::kIsIterationInvariantRate);
  state.counters["rays"] = static_cast<double>(stats.rays);
  state.counters["voxel_visits"] = static_cast<double>(stats.voxel_visits);
  state.counters["known_voxels"] = static_cast<double>(known);
  state.counters["bytes_per_known_voxel"] = static_cast<double>(bytes) / static_cast<double>(known);
  state.counters["memory_MB"] = static_cast<double>(bytes) / 1e6;
  state.counters["scratch_MB"] = static_cast<double>(scratch) / 1e6;
  // The map's parts: block records with their key table, log-odds slabs, class evidence.
  state.counters["records_MB"] = static_cast<double>(parts.records + parts.index) / 1e6;
  state.counters["log_odds_MB"] = static_cast<double>(parts.log_odds) / 1e6;
  state.counters["evidence_MB"] = static_cast<double>(parts.evidence) / 1e6;
}

// Each case runs three times and reports the fastest as "_min" besides the
// mean (fastest_run.hpp says why).
using sarmap::bench::fastest;

BENCHMARK(BM_OctoMap<>)->Name("BM_OctoMap")->ArgNames({"res_mm", "width"})->Args({50, 320})->Args({25, 320})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)
    ->Repetitions(3)->ComputeStatistics("min", fastest);
BENCHMARK(BM_Sarmap<Feed::PerScan>)->Name("BM_Sarmap")->ArgNames({"res_mm", "width", "threads"})
    ->Args({50, 320, 1})->Args({50, 320, 2})->Args({25, 320, 1})->Args({25, 320, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0)
    ->Repetitions(3)->ComputeStatistics("min", fastest);
BENCHMARK(BM_Sarmap<Feed::Sequence>)->Name("BM_SarmapSequence")->ArgNames({"res_mm", "width", "threads"})
    ->Args({50, 320, 1})->Args({50, 320, 2})->Args({25, 320, 1})->Args({25, 320, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0)
    ->Repetitions(3)->ComputeStatistics("min", fastest);
// The scan-by-scan path as a pipeline runs it: 16 MiB is about the memory
// the run's segment and topo stages touch per scan of the default arena.
BENCHMARK(BM_Sarmap<Feed::PerScanCachesEvicted>)->Name("BM_SarmapCachesEvicted")
    ->ArgNames({"res_mm", "width", "threads", "evict_MiB"})->Args({50, 320, 2, 16})->Args({50, 320, 2, 64})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0)
    ->Repetitions(3)->ComputeStatistics("min", fastest);
// The same scan by scan with only time between scans: 5 ms is about what
// the run's other stages take per scan of the default arena, 0 the control
// (the same calls around each scan, no pause).
BENCHMARK(BM_Sarmap<Feed::PerScanPaused>)->Name("BM_SarmapPaused")
    ->ArgNames({"res_mm", "width", "threads", "pause_us"})
    ->Args({50, 320, 1, 0})->Args({50, 320, 1, 5000})->Args({50, 320, 2, 0})->Args({50, 320, 2, 5000})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0)
    ->Repetitions(3)->ComputeStatistics("min", fastest);
// The same pause asleep: a front end fed by its sensor. Its control is
// BM_SarmapPaused's pause_us:0 row.
BENCHMARK(BM_Sarmap<Feed::PerScanIdle>)->Name("BM_SarmapIdle")
    ->ArgNames({"res_mm", "width", "threads", "idle_us"})->Args({50, 320, 1, 5000})->Args({50, 320, 2, 5000})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0)
    ->Repetitions(3)->ComputeStatistics("min", fastest);
// Scaling with image size; OctoMap at 640 x 480 only at 0.05 m (0.025 m takes minutes).
BENCHMARK(BM_OctoMap<>)->Name("BM_OctoMap_640")->ArgNames({"res_mm", "width"})->Args({50, 640})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)
    ->Repetitions(3)->ComputeStatistics("min", fastest);
BENCHMARK(BM_Sarmap<Feed::PerScan>)->Name("BM_Sarmap_640")->ArgNames({"res_mm", "width", "threads"})
    ->Args({50, 640, 2})->Args({25, 640, 1})->Args({25, 640, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0)
    ->Repetitions(3)->ComputeStatistics("min", fastest);
BENCHMARK(BM_Sarmap<Feed::Sequence>)->Name("BM_SarmapSequence_640")->ArgNames({"res_mm", "width", "threads"})
    ->Args({50, 640, 2})->Args({25, 640, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0)
    ->Repetitions(3)->ComputeStatistics("min", fastest);
// A larger map: the building arena at 640 x 480 (OctoMap once per case: a run takes tens of seconds).
BENCHMARK(BM_OctoMap<sarmap::bench::building_arena_sequence>)->Name("BM_OctoMap_Building")
    ->ArgNames({"res_mm", "width"})->Args({50, 640})->Args({25, 640})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_Sarmap<Feed::Sequence, sarmap::bench::building_arena_sequence>)->Name("BM_SarmapSequence_Building")
    ->ArgNames({"res_mm", "width", "threads"})->Args({50, 640, 2})->Args({25, 640, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)
    ->Repetitions(3)->ComputeStatistics("min", fastest);

}  // namespace

// The SIMD level the walk and the key kernel ran at (SARMAP_SIMD forces
// one) goes into the run's context, so a figure carries it.
int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::AddCustomContext("simd_level",
                              std::string(sarmap::kernels::to_string(sarmap::kernels::active_simd_level())));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
