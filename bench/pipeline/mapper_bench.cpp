// The whole pipeline end to end, as `sarmap run` drives it but without file
// I/O: a Mapper over the default arena's 160 simulated scans (320 x 240), with
// each classifier (the DGCNN on the accumulated map, the default, and on each
// scan), at 1 and 2 threads, one scan at a time (Mapper::integrate, as a live
// front end feeds it) or as a stream whose stages overlap
// (Mapper::integrate_stream, as `sarmap run` does). Beside the wall time per
// scan it reports each stage's mean and p95 and the per-scan latency from the
// Mapper's own profile, so one run names the slowest stage, and the metric
// stage's sum to set beside the integrator alone on the same points
// (mapper_integrator_alone_bench.cpp; the labels rows' "_min" with its).
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <string>
#include <vector>

#include "bench/metric/fastest_run.hpp"
#include "bench/metric/sequence_fixture.hpp"
#include "engine/pipeline/mapper.hpp"
#include "engine/sim/simulator.hpp"

namespace {

using namespace sarmap;

const char* const kClassifiers[] = {"labels", "geometric", "dgcnn", "dgcnn-per-scan"};

pipeline::MapperConfig config_for(const std::string& classifier) {
  pipeline::MapperConfig config;
  const bool dgcnn = classifier.rfind("dgcnn", 0) == 0;
  config.classifier.kind = pipeline::classifier_kind_from_name(dgcnn ? "dgcnn" : classifier);
  if (dgcnn) config.classifier.model = SARMAP_SOURCE_DIR "/datasets/models/ramps-dgcnn.safetensors";
  config.classifier.per_scan = classifier == "dgcnn-per-scan";
  return config;
}

void BM_MapperDefaultArena(benchmark::State& state) {
  const std::vector<Scan>& scans = bench::default_arena_sequence(320);
  const std::string classifier = kClassifiers[state.range(0)];
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  const sim::Arena layout = sim::load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  const SensorInfo sensor = sim::sensor_info(layout.sensor);
  StageProfile last;
  for (auto _ : state) {
    arena.execute([&] {
      pipeline::Mapper mapper(config_for(classifier), sensor);
      if (state.range(2) == 0) {
        for (const Scan& scan : scans) {
          Scan copy = scan;  // the Mapper filters a scan's points in place
          mapper.integrate(copy);
        }
      } else {
        mapper.integrate_stream(
            0,
            [&](std::size_t frame, Scan& scan) {
              if (frame >= scans.size()) return false;
              scan = scans[frame];
              return true;
            },
            [](pipeline::StreamedScan&) {});
      }
      mapper.finish();
      last = mapper.profile();
    });
  }
  state.SetLabel(classifier + (state.range(2) == 0 ? ", one by one" : ", stream, stages overlapped"));
  const double n = static_cast<double>(scans.size());
  state.counters["scans_per_s"] =
      benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
  for (const std::string& stage : last.stage_names()) {
    const StageProfile::StageStats s = last.stats(stage);
    state.counters[stage + "_ms"] = s.mean_s * 1e3;
    state.counters[stage + "_p95_ms"] = s.p95_s * 1e3;
  }
  // The metric stage summed over the scans and its rays, to set beside
  // BM_MapperIntegratorAlone (the integrator on the same points, alone).
  state.counters["metric_total_ms"] = last.stats("metric").total_s * 1e3;
  state.counters["metric_rays"] = last.counter("metric", "rays");
  state.counters["latency_p50_ms"] = last.latency().p50_s * 1e3;
  state.counters["latency_p95_ms"] = last.latency().p95_s * 1e3;
}
// The labels rows, a second each, run three times with the fastest run's
// figures as "_min" (every counter's minimum), as the integrator alone
// reports its own: their metric stage is set beside it, and one run carries
// the machine's noise in full. The DGCNN rows, several seconds each, run once.
BENCHMARK(BM_MapperDefaultArena)
    ->ArgNames({"classifier", "threads", "overlap"})
    ->ArgsProduct({{0}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ComputeStatistics("min", sarmap::bench::fastest);
BENCHMARK(BM_MapperDefaultArena)
    ->ArgNames({"classifier", "threads", "overlap"})
    ->ArgsProduct({{1, 2, 3}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(1);

}  // namespace

BENCHMARK_MAIN();
