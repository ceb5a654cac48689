// The topo stage as the pipeline runs it: an arena's simulated scans
// (ground-truth labels) mapped scan by scan, each topological-map update
// timed on its own with the map and segments as they stood after that scan
// and the scan's box as the changed region (as the Mapper passes it), at 1
// and 2 threads. The default arena (160 scans) and the building arena (400
// scans, a map that keeps growing: the first and the last tenth of the
// updates are reported apart, since an update still rebuilds its grid and
// wall scene from the whole map).
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <chrono>

#include "bench/metric/sequence_fixture.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "engine/segments/segment_map.hpp"
#include "engine/topo/topo_map.hpp"

namespace {

using namespace sarmap;

void time_topo_stage(benchmark::State& state, const std::vector<Scan>& scans) {
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  const std::size_t tenth = std::max<std::size_t>(1, scans.size() / 10);
  std::size_t nodes = 0, edges = 0;
  double first_tenth = 0, last_tenth = 0;
  for (auto _ : state) {
    double topo_seconds = 0;
    first_tenth = last_tenth = 0;
    arena.execute([&] {
      metric::MetricMap map;
      metric::IntegratorSettings settings;
      settings.max_range = 5.0;
      metric::RayIntegrator integrator(settings);
      segments::SegmentMap segments;
      topo::TopoMap topo;
      for (std::size_t i = 0; i < scans.size(); ++i) {
        Scan scan = scans[i];
        integrator.integrate(map, scan.points, scan.origin);
        segments.integrate(scan.points, scan.origin);
        Bounds changed = scan.points.bounds();
        changed.extend(scan.origin);
        const auto start = std::chrono::steady_clock::now();
        const topo::TopoUpdate u = topo.update(segments, map, &changed);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        topo_seconds += seconds;
        if (i < tenth) first_tenth += seconds;
        if (i >= scans.size() - tenth) last_tenth += seconds;
        nodes = u.nodes;
        edges = u.edges;
      }
    });
    state.SetIterationTime(topo_seconds);
  }
  state.counters["s_per_scan"] = benchmark::Counter(
      static_cast<double>(scans.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["first_tenth_ms_per_scan"] = 1e3 * first_tenth / static_cast<double>(tenth);
  state.counters["last_tenth_ms_per_scan"] = 1e3 * last_tenth / static_cast<double>(tenth);
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["edges"] = static_cast<double>(edges);
}

void BM_TopoStageDefaultArena(benchmark::State& state) { time_topo_stage(state, bench::default_arena_sequence(320)); }
BENCHMARK(BM_TopoStageDefaultArena)->ArgNames({"threads"})->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseManualTime();

void BM_TopoStageBuildingArena(benchmark::State& state) {
  time_topo_stage(state, bench::building_arena_sequence(320));
}
BENCHMARK(BM_TopoStageBuildingArena)
    ->ArgNames({"threads"})
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
