// The Mapper's metric stage against the integrator's best path, in one run:
// the points the Mapper integrates (the default arena's 160 scans after its
// preprocessing, the "labels" classifier's BM_MapperDefaultArena rows) fed
// to a RayIntegrator with the Mapper's own settings, nothing else running:
// integrate() scan by scan, and integrate_sequence(), which traces the next
// scan while this one is applied, as the Mapper's stream does.
// BM_MapperDefaultArena's metric_total_ms over this row's time is how far
// the users' path is from the benchmark's (PERF.md); both rows are in the
// same binary so that the ratio is read from one run.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <vector>

#include "bench/metric/sequence_fixture.hpp"
#include "bench/metric/fastest_run.hpp"
#include "engine/pipeline/mapper.hpp"
#include "engine/sim/simulator.hpp"

namespace {

using namespace sarmap;

// The scans as the Mapper's preprocess stage leaves them (non-finite points
// and points beyond max_point_distance dropped), once.
std::vector<Scan> preprocessed(const std::vector<Scan>& scans, const pipeline::MapperConfig& config) {
  std::vector<Scan> out = scans;
  for (Scan& scan : out) {
    scan.points.remove_non_finite();
    if (config.max_point_distance > 0) scan.points.remove_farther_than(scan.origin, config.max_point_distance);
  }
  return out;
}

// Args: threads, sequence (0: integrate() per scan, 1: integrate_sequence()).
void BM_MapperIntegratorAlone(benchmark::State& state) {
  pipeline::MapperConfig config;
  config.classifier.kind = pipeline::classifier_kind_from_name("labels");
  const sim::Arena layout = sim::load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  // The Mapper itself says which settings it integrates with.
  const pipeline::Mapper probe(config, sim::sensor_info(layout.sensor));
  metric::IntegratorSettings settings = config.integrator;
  settings.max_range = probe.max_range();
  const metric::MetricMapSettings map_settings = probe.metric_map().settings();
  const std::vector<Scan> scans = preprocessed(bench::default_arena_sequence(320), config);
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  const bool sequence = state.range(1) != 0;
  metric::RayIntegrator integrator(settings);
  std::size_t rays = 0;
  for (auto _ : state) {
    arena.execute([&] {
      metric::MetricMap map(map_settings);
      metric::IntegrationStats stats;
      if (sequence) {
        for (const auto& one : integrator.integrate_sequence(map, scans)) stats += one;
      } else {
        for (const Scan& s : scans) stats += integrator.integrate(map, s.points, s.origin);
      }
      rays = stats.rays;
      benchmark::DoNotOptimize(map.counts().known);
    });
  }
  state.SetLabel(sequence ? "integrate_sequence" : "integrate, scan by scan");
  state.counters["rays"] = static_cast<double>(rays);
}

BENCHMARK(BM_MapperIntegratorAlone)
    ->ArgNames({"threads", "sequence"})
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0)
    ->Repetitions(3)->ComputeStatistics("min", sarmap::bench::fastest);

}  // namespace
