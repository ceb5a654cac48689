// The topo stage as the pipeline runs it: the default arena's 160 simulated
// scans (ground-truth labels) mapped by a Mapper, each topological-map update
// timed on its own (the map and segments as they stood after that scan), at
// 1 and 2 threads.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <chrono>

#include "bench/metric/sequence_fixture.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "engine/segments/segment_map.hpp"
#include "engine/topo/topo_map.hpp"

namespace {

using namespace sarmap;

void BM_TopoStageDefaultArena(benchmark::State& state) {
  const std::vector<Scan>& scans = bench::default_arena_sequence(320);
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  std::size_t nodes = 0, edges = 0;
  for (auto _ : state) {
    double topo_seconds = 0;
    arena.execute([&] {
      metric::MetricMap map;
      metric::IntegratorSettings settings;
      settings.max_range = 5.0;
      metric::RayIntegrator integrator(settings);
      segments::SegmentMap segments;
      topo::TopoMap topo;
      for (Scan scan : scans) {
        integrator.integrate(map, scan.points, scan.origin);
        segments.integrate(scan.points, scan.origin);
        const auto start = std::chrono::steady_clock::now();
        const topo::TopoUpdate u = topo.update(segments, map);
        topo_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        nodes = u.nodes;
        edges = u.edges;
      }
    });
    state.SetIterationTime(topo_seconds);
  }
  state.counters["s_per_scan"] = benchmark::Counter(
      static_cast<double>(scans.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["edges"] = static_cast<double>(edges);
}
BENCHMARK(BM_TopoStageDefaultArena)->ArgNames({"threads"})->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseManualTime();

}  // namespace

BENCHMARK_MAIN();
