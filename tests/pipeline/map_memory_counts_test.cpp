// The segment and topological maps count the memory they hold (what
// profile.json and summary.json report beside the metric map's bytes): each
// count is checked against what the heap holds for the map, on a simulated
// arena, so that a member left out of the count, or counted twice, fails.
// And the topological map's memory follows a bounded map's forgetting.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <memory>
#include <string>
#include <vector>

#include "engine/geometry/triangle_scene.hpp"
#include "engine/metric/map_bounds.hpp"
#include "engine/metric/metric_map.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "engine/segments/segment_map.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/simulator.hpp"
#include "engine/topo/topo_map.hpp"
#include "tests/live_heap_bytes.hpp"
#include "tests/release_only.hpp"

namespace sarmap {
namespace {

std::vector<Scan> default_arena_scans() {
  const sim::Arena arena = sim::load_arena(std::string(SARMAP_SOURCE_DIR) + "/datasets/arenas/esogu-6x4.json");
  const sim::Simulator simulator(arena);
  std::vector<Scan> scans;
  for (std::size_t f = 0; f < simulator.frame_count(); f += 10) scans.push_back(simulator.simulate(f));
  return scans;
}

// The scans into a metric map and a segment map, as a run's stages take them.
void map_scans(const std::vector<Scan>& scans, metric::RayIntegrator& integrator, metric::MetricMap& metric_map,
               segments::SegmentMap& segment_map) {
  for (const Scan& scan : scans) {
    integrator.integrate(metric_map, scan.points, scan.origin);
    segment_map.integrate(scan.points, scan.origin);
  }
}

// The heap's figure may differ from the count by the allocator's overhead
// and its caches of freed chunks: a few per cent and a few hundred KiB, far
// less than any of the maps' large arrays.
void expect_heap_holds(std::size_t held, std::size_t counted, const char* what) {
  const double tolerance = 0.03 * static_cast<double>(counted) + 256.0 * 1024.0;
  EXPECT_NEAR(static_cast<double>(held), static_cast<double>(counted), tolerance) << what;
}

TEST(MapMemoryCounts, SegmentMapCountsWhatTheHeapHoldsForIt) {
  if (kSanitizedBuild) GTEST_SKIP() << "the sanitizers' allocators are not glibc's heap";
  // One thread: no worker's allocations (its task pool) land between the two figures.
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  test::keep_arrays_in_the_heap();
  const std::vector<Scan> scans = default_arena_scans();
  const std::size_t before = test::live_heap_bytes();
  auto map = std::make_unique<segments::SegmentMap>();
  for (const Scan& scan : scans) map->integrate(scan.points, scan.origin);
  const std::size_t held = test::live_heap_bytes() - before;
  ASSERT_GT(map->size(), 5u);  // walls, terrain and ramps: records with members and outlines
  expect_heap_holds(held, sizeof(segments::SegmentMap) + map->memory_bytes(), "segment map");
  // Most of it is the stored points: at least their columns and key index.
  EXPECT_GT(map->memory_bytes(), map->point_count() * (4 * sizeof(float) + 16));
}

TEST(MapMemoryCounts, TopoMapCountsWhatTheHeapHoldsForItBesideEmbree) {
  if (kSanitizedBuild) GTEST_SKIP() << "the sanitizers' allocators are not glibc's heap";
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  test::keep_arrays_in_the_heap();
  const std::vector<Scan> scans = default_arena_scans();
  metric::MetricMap metric_map;
  metric::RayIntegrator integrator;
  segments::SegmentMap segment_map;
  map_scans(scans, integrator, metric_map, segment_map);
  const std::size_t before = test::live_heap_bytes();
  const std::size_t embree_before = geometry::embree_bytes();
  auto topo = std::make_unique<topo::TopoMap>();
  topo->update(segment_map, metric_map);
  // Updates told of no change keep every array, as a run's later scans do.
  const Bounds nothing_changed;
  topo->update(segment_map, metric_map, &nothing_changed);
  const std::size_t held = test::live_heap_bytes() - before;
  const std::size_t embree = geometry::embree_bytes() - embree_before;
  ASSERT_GT(topo->nodes().size(), 5u);
  ASSERT_GT(embree, 0u);  // the wall scene's index and buffers
  // Embree's memory is on the same heap, counted apart (embree_bytes).
  expect_heap_holds(held, sizeof(topo::TopoMap) + topo->memory_bytes() + embree, "topological map");
}

// A bounded map forgets blocks (--max-blocks, --keep-radius); the
// topological map then lets go of what it kept for them (the cached voxel
// columns, the wall scene's tiles and their Embree geometries), so that its
// memory follows the map's rather than the area ever seen: after mapping the
// arena, forgetting it, mapping it again 20 m away and forgetting that too,
// the topological map holds what it held after the first forgetting (the
// arrays it keeps for the largest extent it has seen), not twice as much.
TEST(MapMemoryCounts, TopoMapLetsGoOfWhatTheMapForgot) {
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  std::vector<Scan> scans = default_arena_scans();
  const std::size_t embree_before = geometry::embree_bytes();
  metric::MetricMap metric_map;
  metric::RayIntegrator integrator;
  topo::TopoMap topo;
  const segments::SegmentMap no_segments;
  const Bounds everywhere{Eigen::Vector3d::Constant(-1e3), Eigen::Vector3d::Constant(1e3)};
  std::size_t forgotten_bytes[2] = {0, 0}, forgotten_embree[2] = {0, 0}, mapped_bytes = 0;
  for (int place = 0; place < 2; ++place) {
    segments::SegmentMap segment_map;
    map_scans(scans, integrator, metric_map, segment_map);
    topo.update(segment_map, metric_map, &everywhere);
    ASSERT_GT(topo.walls()->boxes().size(), topo.walls()->segment_boxes());  // voxel boxes in tiles
    mapped_bytes = topo.memory_bytes();
    // Every block forgotten, and the segments with them (as a bounded run's
    // segment stage forgets its points), the change told as a run tells it.
    ASSERT_GT(metric::drop_blocks_beyond(metric_map, Eigen::Vector3d(1e4, 1e4, 0), 1.0), 0u);
    topo.update(no_segments, metric_map, &everywhere);
    EXPECT_TRUE(topo.walls()->boxes().empty());
    forgotten_bytes[place] = topo.memory_bytes();
    forgotten_embree[place] = geometry::embree_bytes() - embree_before;
    for (Scan& scan : scans) {
      for (float& x : scan.points.x()) x += 20.0F;
      scan.origin.x() += 20.0;
    }
  }
  // Without letting go, the second forgetting kept both places' columns and tiles.
  EXPECT_LT(forgotten_bytes[1], forgotten_bytes[0] + mapped_bytes / 10)
      << "after the first forgetting " << forgotten_bytes[0] << ", mapped " << mapped_bytes;
  EXPECT_LT(forgotten_embree[1], forgotten_embree[0] + 64 * 1024) << "after the first " << forgotten_embree[0];
}

}  // namespace
}  // namespace sarmap
