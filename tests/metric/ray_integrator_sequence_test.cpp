// The integrator's two ways of overlapping scans. integrate_sequence(),
// which traces the next scan's rays while this one is written into the
// map: the same map and per-scan figures
// as integrate() on each scan in turn, for 1 and 2 threads and every scratch
// path; an error in any scan (the first, the second, one in the middle, the
// last) leaves exactly the scans before it in the map. And trace() into a
// slot beside apply() of another (as a stream of scans arriving one by one
// runs them): the same map and figures, each traced scan applied once.
#include "engine/metric/ray_integrator.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "engine/core/error.hpp"
#include "tests/metric/maps_identical.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap::metric {
namespace {

using testing::maps_identical;

void expect_same_stats(const IntegrationStats& a, const IntegrationStats& b) {
  EXPECT_EQ(a.points_in, b.points_in);
  EXPECT_EQ(a.points_rejected, b.points_rejected);
  EXPECT_EQ(a.end_voxels, b.end_voxels);
  EXPECT_EQ(a.rays, b.rays);
  EXPECT_EQ(a.voxel_visits, b.voxel_visits);
  EXPECT_EQ(a.hits, b.hits);
  EXPECT_EQ(a.misses, b.misses);
  EXPECT_EQ(a.blocks_created, b.blocks_created);
  EXPECT_EQ(a.dense_walks, b.dense_walks);
  EXPECT_EQ(a.dense_dedupes, b.dense_dedupes);
}

// Scans of the synthetic room, with a far point in some so that their boxes
// differ in size, and (when asked) a point beyond the map limits.
std::vector<Scan> room_scans(int count, int width, int height) {
  testing::SyntheticRoom room;
  std::vector<Scan> scans;
  for (int f = 0; f < count; ++f) {
    auto frame = room.frame(f, count, width, height);
    Scan scan;
    scan.points = std::move(frame.points);
    scan.origin = frame.origin;
    scan.index = static_cast<std::size_t>(f);
    if (f % 3 == 1) {
      scan.points.push_back(40.0f, 3.0f, 1.0f);  // a long ray: a larger box, other blocks
      scan.points.labels()[scan.points.size() - 1] = 1;
    }
    scans.push_back(std::move(scan));
  }
  return scans;
}

TEST(RayIntegratorSequence, SameMapAndFiguresAsOneScanAtATime) {
  const std::vector<Scan> scans = room_scans(7, 96, 72);
  IntegratorSettings dense, hashed, ranged;
  hashed.dense_walk_max_blocks = 0;
  hashed.dense_dedupe_max_cells = 0;
  ranged.max_range = 2.5;
  for (const IntegratorSettings& settings : {dense, hashed, ranged}) {
    for (const int threads : {1, 2}) {
      SCOPED_TRACE(::testing::Message() << threads << " threads, walk dense up to "
                                        << settings.dense_walk_max_blocks << " blocks, max range "
                                        << settings.max_range);
      tbb::task_arena arena(threads);
      MetricMap one_by_one(settings_at_resolution(0.05)), sequenced(settings_at_resolution(0.05));
      RayIntegrator a(settings), b(settings);
      std::vector<IntegrationStats> singles, sequence;
      arena.execute([&] {
        for (const Scan& scan : scans) singles.push_back(a.integrate(one_by_one, scan.points, scan.origin));
        sequence = b.integrate_sequence(sequenced, scans);
      });
      ASSERT_EQ(sequence.size(), scans.size());
      for (std::size_t k = 0; k < scans.size(); ++k) {
        SCOPED_TRACE(::testing::Message() << "scan " << k);
        expect_same_stats(singles[k], sequence[k]);
        EXPECT_GT(sequence[k].misses, 1000u);
      }
      EXPECT_TRUE(maps_identical(one_by_one, sequenced));
      EXPECT_GT(sequenced.counts().occupied, 500u);
    }
  }
}

// The integrator keeps scratch between calls: a sequence after single scans
// and single scans after a sequence give the same map as all one by one.
TEST(RayIntegratorSequence, MixesWithSingleScansOnOneIntegrator) {
  const std::vector<Scan> scans = room_scans(6, 64, 48);
  MetricMap mixed(settings_at_resolution(0.05)), reference(settings_at_resolution(0.05));
  RayIntegrator a, b;
  a.integrate(mixed, scans[0].points, scans[0].origin);
  a.integrate_sequence(mixed, std::span<const Scan>(scans).subspan(1, 4));
  a.integrate(mixed, scans[5].points, scans[5].origin);
  for (const Scan& scan : scans) b.integrate(reference, scan.points, scan.origin);
  EXPECT_TRUE(maps_identical(mixed, reference));
}

TEST(RayIntegratorSequence, EmptySequenceLeavesTheMapAlone) {
  MetricMap map(settings_at_resolution(0.05));
  RayIntegrator integrator;
  EXPECT_TRUE(integrator.integrate_sequence(map, {}).empty());
  EXPECT_TRUE(map.blocks().empty());
}

// A bad scan: the error names the scan and what is wrong, and the map holds
// the scans before it, fully, and nothing of it or after it. The first scan
// fails before the pipeline starts, the second while the first is walked,
// the last when nothing comes after it.
TEST(RayIntegratorSequence, ErrorInOneScanKeepsExactlyTheScansBeforeIt) {
  for (const std::size_t bad : {std::size_t{0}, std::size_t{1}, std::size_t{3}, std::size_t{5}}) {
    for (const bool bad_origin : {false, true}) {
      for (const int threads : {1, 2}) {
        SCOPED_TRACE(::testing::Message() << "scan " << bad << ", " << threads << " threads, bad "
                                          << (bad_origin ? "origin" : "label"));
        std::vector<Scan> scans = room_scans(6, 64, 48);
        if (bad_origin) {
          scans[bad].origin = {std::nan(""), 0.0, 1.0};
        } else {
          scans[bad].points.labels()[100] = 7;
        }
        tbb::task_arena arena(threads);
        MetricMap map(settings_at_resolution(0.05)), before(settings_at_resolution(0.05));
        RayIntegrator integrator, reference;
        arena.execute([&] {
          try {
            integrator.integrate_sequence(map, scans);
            ADD_FAILURE() << "expected an error";
          } catch (const Error& e) {
            EXPECT_EQ(e.code(), bad_origin ? ErrorCode::OutOfRange : ErrorCode::InvalidData);
            const std::string what = e.what();
            EXPECT_EQ(what.rfind("scan " + std::to_string(bad) + ": ", 0), 0u) << what;
            EXPECT_NE(what.find(bad_origin ? "sensor origin" : "point 100 has label 7"), std::string::npos) << what;
          }
        });
        for (std::size_t k = 0; k < bad; ++k) reference.integrate(before, scans[k].points, scans[k].origin);
        EXPECT_TRUE(maps_identical(map, before));
        EXPECT_EQ(map.blocks().empty(), bad == 0);
      }
    }
  }
}

// Scan k + 1 traced in a task while scan k is applied, slots taking turns,
// as Mapper::integrate_stream runs them.
TEST(RayIntegratorTrace, TracingAheadIntoSlotsGivesTheMapOfOneScanAtATime) {
  const std::vector<Scan> scans = room_scans(7, 96, 72);
  for (const int threads : {1, 2}) {
    SCOPED_TRACE(::testing::Message() << threads << " threads");
    tbb::task_arena arena(threads);
    MetricMap one_by_one(settings_at_resolution(0.05)), traced(settings_at_resolution(0.05));
    RayIntegrator a, b;
    std::vector<IntegrationStats> singles, ahead(scans.size());
    arena.execute([&] {
      for (const Scan& scan : scans) singles.push_back(a.integrate(one_by_one, scan.points, scan.origin));
      const double resolution = traced.resolution();
      ahead[0] = b.trace(0, resolution, scans[0].points, scans[0].origin);
      for (std::size_t k = 0; k < scans.size(); ++k) {
        tbb::task_group next;
        if (k + 1 < scans.size()) {
          next.run([&, k] {
            ahead[k + 1] = b.trace((k + 1) % 2, resolution, scans[k + 1].points, scans[k + 1].origin);
          });
        }
        b.apply(traced, k % 2, ahead[k]);
        next.wait();
      }
    });
    for (std::size_t k = 0; k < scans.size(); ++k) {
      SCOPED_TRACE(::testing::Message() << "scan " << k);
      expect_same_stats(singles[k], ahead[k]);
    }
    EXPECT_TRUE(maps_identical(one_by_one, traced));
    EXPECT_GT(traced.counts().occupied, 500u);
  }
}

// apply() takes a slot's traced scan once: not a slot never traced, not a
// scan already applied, not what a trace that threw left behind (even where
// the slot held a scan before), nor a slot the integrator does not have.
TEST(RayIntegratorTrace, ApplyTakesEachTracedScanOnce) {
  std::vector<Scan> scans = room_scans(2, 64, 48);
  MetricMap map(settings_at_resolution(0.05)), reference(settings_at_resolution(0.05));
  RayIntegrator integrator, plain;
  IntegrationStats stats;
  const auto expect_refused = [&](std::size_t slot, const char* what) {
    try {
      integrator.apply(map, slot, stats);
      ADD_FAILURE() << "applied slot " << slot;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_refused(1, "no traced scan");
  stats = integrator.trace(1, map.resolution(), scans[0].points, scans[0].origin);
  integrator.apply(map, 1, stats);
  plain.integrate(reference, scans[0].points, scans[0].origin);
  expect_refused(1, "no traced scan");

  stats = integrator.trace(0, map.resolution(), scans[1].points, scans[1].origin);
  scans[1].points.labels()[10] = 9;  // not a class id
  EXPECT_THROW(integrator.trace(0, map.resolution(), scans[1].points, scans[1].origin), Error);
  expect_refused(0, "no traced scan");
  EXPECT_TRUE(maps_identical(map, reference));

  EXPECT_THROW(integrator.trace(RayIntegrator::kSlots, map.resolution(), scans[0].points, scans[0].origin),
               Error);
  expect_refused(RayIntegrator::kSlots, "not one of");
}

}  // namespace
}  // namespace sarmap::metric
