// The segment stage: the default arena's 160 simulated scans (ground-truth
// labels, Kinect noise) through a SegmentMap, a 300 k-point labelled cloud in
// one call, and the plane search itself (RANSAC, least squares, region
// growing) on 100 k points of one class, at 1 and 2 threads.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <random>

#include "bench/metric/sequence_fixture.hpp"
#include "engine/segments/plane_extraction.hpp"
#include "engine/segments/segment_map.hpp"

namespace {

using namespace sarmap;

// Scans in 0.5 m stripes of a 10 x 6 m room: floor, four walls, three
// platforms and a doorway wall, sampled every 1.9 cm with 3 mm noise: about
// 300 k labelled points.
PointBuffer labelled_room(std::size_t& count) {
  struct Patch {
    Eigen::Vector3d corner, a, b;
    ClassId label;
  };
  const std::vector<Patch> patches = {
      {{0, 0, 0}, {10, 0, 0}, {0, 6, 0}, ClassId::Terrain},   {{0, 0, 0}, {10, 0, 0}, {0, 0, 1.2}, ClassId::Wall},
      {{0, 6, 0}, {10, 0, 0}, {0, 0, 1.2}, ClassId::Wall},    {{0, 0, 0}, {0, 6, 0}, {0, 0, 1.2}, ClassId::Wall},
      {{10, 0, 0}, {0, 6, 0}, {0, 0, 1.2}, ClassId::Wall},    {{5, 0, 0}, {0, 2.6, 0}, {0, 0, 1.2}, ClassId::Wall},
      {{5, 3.4, 0}, {0, 2.6, 0}, {0, 0, 1.2}, ClassId::Wall}, {{1, 1, 0.3}, {1.2, 0, 0}, {0, 1, 0}, ClassId::FlatRamp},
      {{7, 1, 0.2}, {1, 0, 0}, {0, 1.5, 0}, ClassId::FlatRamp}, {{7, 4, 0.4}, {1.5, 0, 0}, {0, 1, 0}, ClassId::FlatRamp}};
  PointBuffer out;
  out.enable_labels();
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 0.003);
  for (const Patch& p : patches) {
    const Eigen::Vector3d n = p.a.cross(p.b).normalized();
    const int na = static_cast<int>(p.a.norm() / 0.019), nb = static_cast<int>(p.b.norm() / 0.019);
    for (int i = 0; i <= na; ++i) {
      for (int k = 0; k <= nb; ++k) {
        const Eigen::Vector3d q = p.corner + p.a * (i / double(na)) + p.b * (k / double(nb)) + n * noise(rng);
        out.push_back(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
        out.labels()[out.size() - 1] = static_cast<std::uint8_t>(p.label);
      }
    }
  }
  count = out.size();
  return out;
}

void BM_SegmentStageDefaultArena(benchmark::State& state) {
  const std::vector<Scan>& scans = bench::default_arena_sequence(320);
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  std::size_t segments = 0;
  for (auto _ : state) {
    arena.execute([&] {
      segments::SegmentMap map;
      for (const Scan& scan : scans) map.integrate(scan.points, scan.origin);
      segments = map.size();
    });
  }
  state.counters["s_per_scan"] = benchmark::Counter(
      static_cast<double>(scans.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["points_per_second"] =
      benchmark::Counter(static_cast<double>(bench::total_points(scans)), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["segments"] = static_cast<double>(segments);
}
BENCHMARK(BM_SegmentStageDefaultArena)->ArgNames({"threads"})->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SegmentMapCloud300k(benchmark::State& state) {
  std::size_t count = 0;
  const PointBuffer cloud = labelled_room(count);
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  std::size_t segments = 0;
  segments::SegmentSettings settings;
  settings.max_range = 0;
  for (auto _ : state) {
    arena.execute([&] {
      segments::SegmentMap map(settings);
      map.integrate(cloud, {5, 3, 1});
      segments = map.size();
    });
  }
  state.counters["points"] = static_cast<double>(count);
  state.counters["points_per_second"] = benchmark::Counter(static_cast<double>(count), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["segments"] = static_cast<double>(segments);
}
BENCHMARK(BM_SegmentMapCloud300k)->ArgNames({"threads"})->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The plane search alone on 100 k wall points (six walls, two of them on one line with a doorway between).
void BM_PlaneSearch100k(benchmark::State& state) {
  std::size_t count = 0;
  const PointBuffer room = labelled_room(count);
  std::vector<float> x, y, z;
  for (std::size_t i = 0; i < room.size(); ++i) {
    if (room.labels()[i] != static_cast<std::uint8_t>(ClassId::Wall)) continue;
    x.push_back(room.x()[i]);
    y.push_back(room.y()[i]);
    z.push_back(room.z()[i]);
  }
  // Every wall, thinned evenly to 100 k points.
  const std::size_t keep = std::min<std::size_t>(100000, x.size());
  for (std::size_t k = 0; k < keep; ++k) {
    const std::size_t from = k * x.size() / keep;
    x[k] = x[from];
    y[k] = y[from];
    z[k] = z[from];
  }
  x.resize(keep);
  y.resize(keep);
  z.resize(keep);
  const segments::PlanePoints points{x, y, z};
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  std::size_t surfaces = 0, planes = 0;
  for (auto _ : state) {
    arena.execute([&] {
      const segments::Extraction e = segments::extract_surfaces(points, {}, 7);
      surfaces = e.surfaces.size();
      planes = e.planes;
    });
  }
  state.counters["points"] = static_cast<double>(x.size());
  state.counters["planes"] = static_cast<double>(planes);
  state.counters["surfaces"] = static_cast<double>(surfaces);
}
BENCHMARK(BM_PlaneSearch100k)->ArgNames({"threads"})->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
