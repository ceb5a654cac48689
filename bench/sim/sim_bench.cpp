// Simulated points per second on the default arena (esogu-6x4, 320 x 240
// depth camera, Kinect noise), at 1 and 2 threads, with single rays and with
// 16-ray packets; and the ground-truth voxelisation of the same arena.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "engine/sim/arena.hpp"
#include "engine/sim/ground_truth_grid.hpp"
#include "engine/sim/simulator.hpp"

namespace {

using namespace sarmap::sim;

const Arena& default_arena() {
  static const Arena arena = load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  return arena;
}

// Arguments: threads, batch mode (0 single rays, 1 packets of 16).
void BM_SimulateFrames(benchmark::State& state) {
  const auto threads = static_cast<int>(state.range(0));
  const auto mode = state.range(1) == 0 ? RayBatchMode::Single : RayBatchMode::Packet16;
  const Simulator sim(default_arena(), {.seed = 1, .batch_mode = mode});
  tbb::task_arena arena(threads);
  constexpr std::size_t kFrames[] = {0, 40, 80, 120};
  std::size_t points = 0, rays = 0;
  for (auto _ : state) {
    arena.execute([&] {
      for (std::size_t f : kFrames) {
        const sarmap::Scan scan = sim.simulate(f);
        points += scan.points.size();
        rays += sim.rays().directions.size();
        benchmark::DoNotOptimize(scan.points.x().data());
      }
    });
  }
  state.counters["points_per_second"] = benchmark::Counter(static_cast<double>(points), benchmark::Counter::kIsRate);
  state.counters["rays_per_second"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SimulateFrames)
    ->ArgNames({"threads", "packet16"})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Surface voxels only (triangle clipping), 5 cm.
void BM_GroundTruthSurfaces(benchmark::State& state) {
  for (auto _ : state) {
    const GroundTruthGrid g = voxelize_arena(default_arena(), {.resolution = 0.05, .compute_free = false});
    benchmark::DoNotOptimize(g.occupied.size());
  }
}
BENCHMARK(BM_GroundTruthSurfaces)->Unit(benchmark::kMillisecond);

// Surfaces plus free space from every 8th frame (20 frames), all rays, 5 cm, 2 threads.
void BM_GroundTruthWithFreeSpace(benchmark::State& state) {
  const Simulator sim(default_arena(), {.noise = false});
  tbb::task_arena arena(2);
  for (auto _ : state) {
    arena.execute([&] {
      const GroundTruthGrid g = voxelize_arena(sim, {.resolution = 0.05, .frame_stride = 8});
      benchmark::DoNotOptimize(g.free.size());
    });
  }
}
BENCHMARK(BM_GroundTruthWithFreeSpace)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
