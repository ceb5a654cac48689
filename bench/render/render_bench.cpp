// What `sarmap render` spends its time on, on a synthetic arena the size of
// the default one (6 x 4 m at 0.05 m: floor, 1.2 m walls, a platform and a
// stepped ramp, about 25,000 voxels): building the face scene, casting the
// two 3-D views, the top view with its overlays, and encoding the PNG.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "engine/render/camera.hpp"
#include "engine/render/png_file.hpp"
#include "engine/render/top_view.hpp"
#include "engine/render/voxel_scene.hpp"
#include "engine/render/voxel_views.hpp"

namespace sarmap::render {
namespace {

constexpr float kVoxel = 0.05f;

VoxelSet arena_voxels() {
  VoxelSet set;
  set.voxel = kVoxel;
  const auto add = [&set](int x, int y, int z, ClassId label) {
    set.centres.emplace_back((x + 0.5f) * kVoxel, (y + 0.5f) * kVoxel, (z + 0.5f) * kVoxel);
    set.labels.push_back(label);
  };
  for (int x = 0; x < 120; ++x) {
    for (int y = 0; y < 80; ++y) {
      const bool wall = x == 0 || y == 0 || x == 119 || y == 79;
      add(x, y, 0, ClassId::Terrain);
      for (int z = 1; wall && z < 24; ++z) add(x, y, z, ClassId::Wall);
      if (!wall && x >= 78 && x < 102 && y >= 6 && y < 26) {  // a 0.3 m platform
        for (int z = 1; z < 7; ++z) add(x, y, z, ClassId::FlatRamp);
      }
      if (!wall && x >= 18 && x < 42 && y >= 6 && y < 26) {  // a ramp rising along +x
        for (int z = 1; z <= (x - 18) / 4; ++z) add(x, y, z, ClassId::InclinedRamp);
      }
    }
  }
  return set;
}

const VoxelSet& voxels() {
  static const VoxelSet set = arena_voxels();
  return set;
}

void BM_VoxelSceneBuild(benchmark::State& state) {
  for (auto _ : state) {
    VoxelScene scene(voxels());
    benchmark::DoNotOptimize(scene.face_count());
  }
  state.counters["voxels"] = static_cast<double>(voxels().centres.size());
}
BENCHMARK(BM_VoxelSceneBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

// The metric and semantic views of one oblique camera, w x h each.
void BM_VoxelViews(benchmark::State& state) {
  const VoxelScene scene(voxels());
  const Box3 box = voxel_bounds(voxels());
  const auto w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const Camera camera = oblique_camera(box, w, h);
  for (auto _ : state) {
    const VoxelViews views = render_voxel_views(scene, voxels(), camera, {box.min.z(), box.max.z()});
    benchmark::DoNotOptimize(views.metric.bytes().data());
  }
  state.counters["pixels/s"] =
      benchmark::Counter(static_cast<double>(w) * h, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_VoxelViews)->Args({1280, 720})->Args({640, 360})->Unit(benchmark::kMillisecond)->UseRealTime();

MapOverlays graph_overlays() {
  MapOverlays overlays;
  for (std::uint32_t i = 0; i < 40; ++i) {
    topo::TopoNode n;
    n.id = i;
    n.position = {0.5 + 0.7 * (i % 8), 0.5 + 0.7 * (i / 8), 0.05};
    overlays.nodes.push_back(n);
  }
  for (std::uint32_t i = 0; i < 120; ++i) {
    overlays.edges.push_back({i % 40, (i * 7 + 3) % 40, 1.0, 0.0, ClassId::Terrain, i % 3 == 0});
  }
  return overlays;
}

// The view from above with a graph of 40 nodes and 120 edges over it.
void BM_TopView(benchmark::State& state) {
  const VoxelScene scene(voxels());
  const Camera camera = top_down_camera(voxel_bounds(voxels()), 1280, 720);
  const MapOverlays overlays = graph_overlays();
  for (auto _ : state) {
    const RgbImage image = render_top_view(scene, voxels(), camera, overlays);
    benchmark::DoNotOptimize(image.bytes().data());
  }
}
BENCHMARK(BM_TopView)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same graph drawn alone (one thread).
void BM_TopViewOverlays(benchmark::State& state) {
  const Camera camera = top_down_camera(voxel_bounds(voxels()), 1280, 720);
  const MapOverlays overlays = graph_overlays();
  RgbImage image(1280, 720);
  for (auto _ : state) {
    draw_overlays(image, camera, overlays);
    benchmark::DoNotOptimize(image.bytes().data());
  }
}
BENCHMARK(BM_TopViewOverlays)->Unit(benchmark::kMillisecond)->UseRealTime();

// Encoding and atomically writing a picture of three 1280 x 720 views.
void BM_WritePng(benchmark::State& state) {
  const VoxelScene scene(voxels());
  const Box3 box = voxel_bounds(voxels());
  const VoxelViews views =
      render_voxel_views(scene, voxels(), oblique_camera(box, 1280, 720), {box.min.z(), box.max.z()});
  RgbImage picture(2572, 1452);
  picture.paste(views.metric, 4, 4);
  picture.paste(views.semantic, 1288, 4);
  picture.paste(views.semantic, 644, 728);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("sarmap_render_bench_" + std::to_string(::getpid()) + ".png");
  for (auto _ : state) write_png(picture, file);
  state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(file));
  std::filesystem::remove(file);
}
BENCHMARK(BM_WritePng)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace sarmap::render

BENCHMARK_MAIN();
