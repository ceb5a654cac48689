// The classify stage as the pipeline runs it: the default arena's 160
// simulated scans (320 x 240) classified one after the other by the
// pipeline's PointClassifier, each call timed on its own, at 1 and 2
// threads: the DGCNN on the accumulated map (the default) with and without
// the rules after the network, the DGCNN on each scan, and the geometric
// baseline. The rest of the pipeline does not run: the classifier reads
// nothing but its scans. (BENCHMARK_MAIN is topo_stage_bench.cpp's: one
// binary, sarmap_pipeline_bench.)
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "bench/metric/sequence_fixture.hpp"
#include "engine/pipeline/point_classifier.hpp"

namespace {

using namespace sarmap;

const char* const kVariants[] = {"dgcnn on the map", "dgcnn on the map, no rules", "dgcnn per scan", "geometric"};

pipeline::ClassifierConfig config_for(int variant) {
  pipeline::ClassifierConfig c;
  c.kind = variant == 3 ? pipeline::ClassifierKind::Geometric : pipeline::ClassifierKind::Dgcnn;
  c.model = SARMAP_SOURCE_DIR "/datasets/models/ramps-dgcnn.safetensors";
  c.per_scan = variant == 2;
  if (variant == 1) {
    for (std::string_view rule : kRuleNames) rule_enabled(c.rules, rule) = false;
  }
  return c;
}

void BM_ClassifyStageDefaultArena(benchmark::State& state) {
  const std::vector<Scan>& scans = bench::default_arena_sequence(320);
  const int variant = static_cast<int>(state.range(0));
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  std::vector<double> per_scan;
  std::size_t blocks = 0;
  for (auto _ : state) {
    double seconds = 0;
    per_scan.clear();
    blocks = 0;
    arena.execute([&] {
      const auto classifier = pipeline::make_point_classifier(config_for(variant));
      for (const Scan& scan : scans) {
        PointBuffer points = scan.points;  // classify writes the labels in place
        const auto start = std::chrono::steady_clock::now();
        blocks += classifier->classify(points).blocks;
        per_scan.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        seconds += per_scan.back();
      }
    });
    state.SetIterationTime(seconds);
  }
  state.SetLabel(kVariants[variant]);
  std::sort(per_scan.begin(), per_scan.end());
  const auto at = [&](double p) { return per_scan[static_cast<std::size_t>(p * static_cast<double>(per_scan.size() - 1))]; };
  double total = 0;
  for (double t : per_scan) total += t;
  state.counters["mean_ms"] = total * 1e3 / static_cast<double>(per_scan.size());
  state.counters["p50_ms"] = at(0.50) * 1e3;
  state.counters["p95_ms"] = at(0.95) * 1e3;
  state.counters["blocks"] = static_cast<double>(blocks);
}
BENCHMARK(BM_ClassifyStageDefaultArena)
    ->ArgNames({"classifier", "threads"})
    ->ArgsProduct({{0, 1, 2, 3}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(1);

}  // namespace
