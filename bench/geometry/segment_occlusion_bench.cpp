// The topological map's edge-against-wall test: candidate edges against thin
// wall boxes, as TriangleScene::segments_blocked (Embree, scene build timed
// too) and as a brute-force loop of the exact segment_intersects_box, serial
// and TBB-parallel, side by side over {1k, 10k, 100k} edges x {100, 1k, 10k}
// walls, so the ratio is measured on the same data and threads.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "engine/geometry/oriented_box.hpp"
#include "engine/geometry/segment_box.hpp"
#include "engine/geometry/triangle_scene.hpp"

namespace {

using namespace sarmap::geometry;

// One wall per 6 m^2: the 0.37 m of wall per m^2 of datasets/arenas/building-52x15
// with walls 2.25 m long on average, so the area grows with the wall count.
constexpr double kAreaPerWall = 6.0;

struct Workload {
  std::vector<OrientedBox> walls;
  std::vector<Segment> edges;
};

// Walls 0.1 m thick, 1.2 m tall, 0.5-4 m long at any yaw; edges 0.2-2 m long
// (horizontally) between points 0.1-0.5 m above the floor. Seeded by size.
const Workload& workload(std::size_t edges, std::size_t walls) {
  static std::map<std::pair<std::size_t, std::size_t>, Workload> cache;
  auto [it, fresh] = cache.try_emplace({edges, walls});
  if (!fresh) return it->second;
  Workload& w = it->second;
  std::mt19937_64 rng(edges * 31 + walls);
  std::uniform_real_distribution<double> u(0, 1);
  const double side = std::sqrt(kAreaPerWall * static_cast<double>(walls));
  for (std::size_t i = 0; i < walls; ++i) {
    w.walls.push_back(yawed_box({side * u(rng), side * u(rng), 0.6}, {0.5 + 3.5 * u(rng), 0.1, 1.2},
                                2 * std::numbers::pi * u(rng)));
  }
  for (std::size_t i = 0; i < edges; ++i) {
    const Eigen::Vector3d p(side * u(rng), side * u(rng), 0.1 + 0.4 * u(rng));
    const double yaw = 2 * std::numbers::pi * u(rng);
    const double length = 0.2 + 1.8 * u(rng);
    const Eigen::Vector3d q(p.x() + length * std::cos(yaw), p.y() + length * std::sin(yaw),
                            0.1 + 0.4 * u(rng));
    w.edges.push_back({p, q});
  }
  return w;
}

// All walls as one mesh (merged), or one mesh per wall.
std::vector<ClassedMesh> wall_meshes(const std::vector<OrientedBox>& walls, bool merged = true) {
  std::vector<ClassedMesh> meshes;
  if (merged) {
    meshes.resize(1);
    meshes[0].vertices.reserve(8 * walls.size());
    meshes[0].indices.reserve(36 * walls.size());
    for (const OrientedBox& b : walls) append_box(meshes[0], b);
  } else {
    meshes.reserve(walls.size());
    for (const OrientedBox& b : walls) meshes.push_back(box_mesh(b));
  }
  for (ClassedMesh& m : meshes) m.label = sarmap::ClassId::Wall;
  return meshes;
}

// The brute force: every edge against every wall until one blocks it.
void brute_force(const Workload& w, std::size_t begin, std::size_t end, std::vector<std::uint8_t>& blocked) {
  for (std::size_t i = begin; i < end; ++i) {
    std::uint8_t hit = 0;
    for (const OrientedBox& b : w.walls) {
      if (segment_intersects_box(w.edges[i], b)) {
        hit = 1;
        break;
      }
    }
    blocked[i] = hit;
  }
}

void set_counters(benchmark::State& state, const Workload& w, const std::vector<std::uint8_t>& blocked) {
  std::size_t count = 0;
  for (std::uint8_t b : blocked) count += b;
  state.counters["edges_per_second"] =
      benchmark::Counter(static_cast<double>(w.edges.size()) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
  state.counters["blocked_fraction"] = static_cast<double>(count) / static_cast<double>(w.edges.size());
}

// Arguments: edges, walls, threads, mode (0 single rays, 1 packets of 16),
// build quality (0 low, 1 medium, 2 high). Boxes to meshes, scene build and
// queries are all timed: the topo map rebuilds its wall scene as walls grow.
void BM_Embree(benchmark::State& state) {
  const Workload& w =
      workload(static_cast<std::size_t>(state.range(0)), static_cast<std::size_t>(state.range(1)));
  const auto mode = state.range(3) == 0 ? RayBatchMode::Single : RayBatchMode::Packet16;
  const auto quality = static_cast<BuildQuality>(state.range(4));
  tbb::task_arena arena(static_cast<int>(state.range(2)));
  std::vector<std::uint8_t> blocked(w.edges.size());
  for (auto _ : state) {
    arena.execute([&] {
      const TriangleScene scene(wall_meshes(w.walls), quality);
      scene.segments_blocked(w.edges, blocked, mode);
    });
    benchmark::DoNotOptimize(blocked.data());
  }
  set_counters(state, w, blocked);
}

// The parts of BM_Embree apart (arguments: edges, walls, threads, quality):
// the scene build alone, and the queries on a scene built beforehand.
void BM_EmbreeBuildOnly(benchmark::State& state) {
  const Workload& w =
      workload(static_cast<std::size_t>(state.range(0)), static_cast<std::size_t>(state.range(1)));
  tbb::task_arena arena(static_cast<int>(state.range(2)));
  for (auto _ : state) {
    arena.execute([&] {
      const TriangleScene scene(wall_meshes(w.walls, state.range(4) != 0),
                                static_cast<BuildQuality>(state.range(3)));
      benchmark::DoNotOptimize(&scene);
    });
  }
}

void BM_EmbreeQueryOnly(benchmark::State& state) {
  const Workload& w =
      workload(static_cast<std::size_t>(state.range(0)), static_cast<std::size_t>(state.range(1)));
  const auto mode = state.range(3) == 0 ? RayBatchMode::Single : RayBatchMode::Packet16;
  tbb::task_arena arena(static_cast<int>(state.range(2)));
  const TriangleScene scene(wall_meshes(w.walls), static_cast<BuildQuality>(state.range(4)));
  std::vector<std::uint8_t> blocked(w.edges.size());
  for (auto _ : state) {
    arena.execute([&] { scene.segments_blocked(w.edges, blocked, mode); });
    benchmark::DoNotOptimize(blocked.data());
  }
  set_counters(state, w, blocked);
}

// Arguments: edges, walls, threads (1 runs the plain serial loop, with no TBB).
// Also counts the edges where it and Embree disagree (segments within the
// float tolerance of a wall, or lying wholly inside one).
void BM_BruteForce(benchmark::State& state) {
  const Workload& w =
      workload(static_cast<std::size_t>(state.range(0)), static_cast<std::size_t>(state.range(1)));
  const auto threads = static_cast<int>(state.range(2));
  tbb::task_arena arena(threads);
  std::vector<std::uint8_t> blocked(w.edges.size());
  for (auto _ : state) {
    if (threads == 1) {
      brute_force(w, 0, w.edges.size(), blocked);
    } else {
      arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, w.edges.size(), 64),
            [&](const tbb::blocked_range<std::size_t>& r) { brute_force(w, r.begin(), r.end(), blocked); });
      });
    }
    benchmark::DoNotOptimize(blocked.data());
  }
  set_counters(state, w, blocked);
  std::vector<std::uint8_t> embree(w.edges.size());
  arena.execute(
      [&] { TriangleScene(wall_meshes(w.walls), BuildQuality::Low).segments_blocked(w.edges, embree); });
  // Where Embree and the exact test differ, say why: an edge lying wholly
  // inside a wall (no surface crossed), one within the float tolerance of a
  // wall's surface, or neither (a real disagreement: should stay 0).
  std::size_t inside = 0, near = 0, other = 0;
  for (std::size_t i = 0; i < embree.size(); ++i) {
    if (embree[i] == blocked[i]) continue;
    const Segment& e = w.edges[i];
    bool is_inside = false, is_near = false;
    for (const OrientedBox& b : w.walls) {
      is_inside = is_inside || (signed_distance(e.p, b) < 0 && signed_distance(e.q, b) < 0);
      is_near = is_near || segment_near_box_surface(e, b);
    }
    (is_inside ? inside : is_near ? near : other) += 1;
  }
  state.counters["differ_inside_wall"] = static_cast<double>(inside);
  state.counters["differ_near_surface"] = static_cast<double>(near);
  state.counters["differ_other"] = static_cast<double>(other);
}

constexpr std::int64_t kEdges[] = {1000, 10000, 100000};
constexpr std::int64_t kWalls[] = {100, 1000, 10000};

void register_all() {
  const auto ms = benchmark::kMillisecond;
  // The grid: Embree as the topo map would use it (all walls one mesh, low
  // build quality: the build dominates), both ray modes, against the brute
  // force serial and on as many threads.
  for (std::int64_t walls : kWalls) {
    for (std::int64_t edges : kEdges) {
      for (std::int64_t mode : {0, 1}) {
        benchmark::RegisterBenchmark("BM_Embree", BM_Embree)
            ->ArgNames({"edges", "walls", "threads", "packet16", "quality"})
            ->Args({edges, walls, 2, mode, 0})
            ->Unit(ms)
            ->UseRealTime();
      }
      for (std::int64_t mode : {0, 1}) {
        benchmark::RegisterBenchmark("BM_EmbreeQueryOnly", BM_EmbreeQueryOnly)
            ->ArgNames({"edges", "walls", "threads", "packet16", "quality"})
            ->Args({edges, walls, 2, mode, 0})
            ->Unit(ms)
            ->UseRealTime();
      }
      for (std::int64_t threads : {1, 2}) {
        auto* b = benchmark::RegisterBenchmark("BM_BruteForce", BM_BruteForce)
                      ->ArgNames({"edges", "walls", "threads"})
                      ->Args({edges, walls, threads})
                      ->Unit(ms)
                      ->UseRealTime();
        // 1e8 and more box tests take seconds: one run says enough.
        if (edges * walls >= 100000000) b->Iterations(1);
      }
    }
  }
  // The target case (10k edges, 1k walls) taken apart: build qualities and
  // threads; the build alone, with one mesh per wall or one for all; the
  // queries alone on the better BVHs.
  for (std::int64_t quality : {0, 1, 2}) {
    for (std::int64_t threads : {1, 2}) {
      benchmark::RegisterBenchmark("BM_Embree", BM_Embree)
          ->ArgNames({"edges", "walls", "threads", "packet16", "quality"})
          ->Args({10000, 1000, threads, 1, quality})
          ->Unit(ms)
          ->UseRealTime();
      for (std::int64_t merged : {0, 1}) {
        benchmark::RegisterBenchmark("BM_EmbreeBuildOnly", BM_EmbreeBuildOnly)
            ->ArgNames({"edges", "walls", "threads", "quality", "merged"})
            ->Args({10000, 1000, threads, quality, merged})
            ->Unit(ms)
            ->UseRealTime();
      }
    }
    if (quality == 0) continue;
    for (std::int64_t mode : {0, 1}) {
      benchmark::RegisterBenchmark("BM_EmbreeQueryOnly", BM_EmbreeQueryOnly)
          ->ArgNames({"edges", "walls", "threads", "packet16", "quality"})
          ->Args({10000, 1000, 2, mode, quality})
          ->Unit(ms)
          ->UseRealTime();
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
