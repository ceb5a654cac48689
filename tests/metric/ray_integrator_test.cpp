// The parallel integrator: hand-worked rays, OctoMap's per-scan semantics,
// bit-identical maps for 1 and 2 threads, and agreement with a plain serial
// reference (std::set of voxels per scan, written into dense blocks of
// SemanticVoxel: the map's representation before compact blocks) on a
// synthetic room.
#include "engine/metric/ray_integrator.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>
#include <map>
#include <set>
#include <tuple>

#include <tbb/task_arena.h>

#include "engine/core/error.hpp"
#include "engine/metric/voxel_ray.hpp"
#include "tests/metric/maps_identical.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap::metric {
namespace {

constexpr double kRes = 0.05;

PointBuffer cloud(std::initializer_list<Eigen::Vector3f> pts, std::uint8_t label = 2) {
  PointBuffer b;
  b.enable_labels();
  for (const auto& p : pts) {
    b.push_back(p.x(), p.y(), p.z());
    b.labels()[b.size() - 1] = label;
  }
  return b;
}

std::int16_t log_odds(const MetricMap& m, VoxelKey k) {
  const std::optional<SemanticVoxel> v = m.blocks().voxel(k);
  return v ? v->log_odds : kUnknownLogOdds;
}

using testing::maps_identical;

// The reference's map: every block as 512 SemanticVoxel, by block key.
using DenseMap = std::map<std::tuple<int, int, int>, DenseVoxels>;

// The map holds exactly the reference's blocks, voxel for voxel.
bool same_as_dense(const MetricMap& map, const DenseMap& dense) {
  if (map.blocks().block_count() != dense.size()) return false;
  for (const auto& [key, voxels] : dense) {
    const auto& [x, y, z] = key;
    const SemanticBlock* block = map.blocks().find(BlockKey{x, y, z});
    if (block == nullptr) return false;
    const DenseVoxels ours = block->dense();
    if (std::memcmp(ours.data(), voxels.data(), sizeof(ours)) != 0) return false;
  }
  return true;
}

TEST(RayIntegrator, SingleRayMarksMissesThenAHit) {
  MetricMap map(settings_at_resolution(kRes));
  RayIntegrator integrator;
  const auto stats = integrator.integrate(map, cloud({{0.525f, 0.025f, 0.025f}}), {0.025, 0.025, 0.025});
  EXPECT_EQ(stats.rays, 1u);
  EXPECT_EQ(stats.hits, 1u);
  EXPECT_EQ(stats.misses, 10u);
  EXPECT_EQ(stats.voxel_visits, 10u);
  for (int x = 0; x < 10; ++x) EXPECT_EQ(log_odds(map, {x, 0, 0}), map.occupancy().miss()) << x;
  EXPECT_EQ(log_odds(map, {10, 0, 0}), map.occupancy().hit());
  EXPECT_EQ(map.state({10, 0, 0}), VoxelState::Occupied);
  EXPECT_EQ(map.state({11, 0, 0}), VoxelState::Unknown);
  EXPECT_EQ(map.state({5, 1, 0}), VoxelState::Unknown);
  EXPECT_EQ(map.class_of({10, 0, 0}), ClassId::Wall);
}

TEST(RayIntegrator, LogOddsClampLikeOctoMap) {
  MetricMap map(settings_at_resolution(kRes));
  RayIntegrator integrator;
  for (int i = 0; i < 10; ++i) integrator.integrate(map, cloud({{0.525f, 0.025f, 0.025f}}), {0.025, 0.025, 0.025});
  EXPECT_EQ(log_odds(map, {10, 0, 0}), map.occupancy().max());
  EXPECT_EQ(log_odds(map, {3, 0, 0}), map.occupancy().min());
  EXPECT_NEAR(OccupancyModel::probability(map.occupancy().max()), 0.97, 1e-3);
}

TEST(RayIntegrator, EndPointsInOneVoxelCastOnceAndHitsWinOverMisses) {
  MetricMap map(settings_at_resolution(kRes));
  RayIntegrator integrator;
  // Two points in voxel (10,0,0), one in voxel (5,0,0) on the same line of sight.
  const auto stats = integrator.integrate(
      map, cloud({{0.51f, 0.02f, 0.03f}, {0.54f, 0.03f, 0.02f}, {0.27f, 0.025f, 0.025f}}), {0.025, 0.025, 0.025});
  EXPECT_EQ(stats.end_voxels, 2u);
  EXPECT_EQ(stats.rays, 2u);
  EXPECT_EQ(stats.hits, 2u);
  EXPECT_EQ(log_odds(map, {5, 0, 0}), map.occupancy().hit());  // hit, not also a miss
  EXPECT_EQ(log_odds(map, {4, 0, 0}), map.occupancy().miss());  // once, though two rays cross it
}

TEST(RayIntegrator, ZeroLengthRayAndOriginInsideAnOccupiedVoxel) {
  MetricMap map(settings_at_resolution(kRes));
  RayIntegrator integrator;
  // A point in the origin's own voxel: a hit, nothing walked.
  auto stats = integrator.integrate(map, cloud({{0.03f, 0.03f, 0.03f}}), {0.025, 0.025, 0.025});
  EXPECT_EQ(stats.voxel_visits, 0u);
  EXPECT_EQ(stats.misses, 0u);
  EXPECT_EQ(map.state({0, 0, 0}), VoxelState::Occupied);
  // Now the sensor sits in that occupied voxel and sees a point further on:
  // its own voxel is on the ray and takes a miss (OctoMap's semantics).
  stats = integrator.integrate(map, cloud({{0.225f, 0.025f, 0.025f}}), {0.025, 0.025, 0.025});
  EXPECT_EQ(stats.misses, 4u);
  EXPECT_EQ(log_odds(map, {0, 0, 0}), map.occupancy().hit() + map.occupancy().miss());
  EXPECT_EQ(map.state({4, 0, 0}), VoxelState::Occupied);
}

TEST(RayIntegrator, MaxRangeCutsRaysIntoMissesOnly) {
  MetricMap map(settings_at_resolution(kRes));
  IntegratorSettings s;
  s.max_range = 0.5;
  RayIntegrator integrator(s);
  const auto stats = integrator.integrate(map, cloud({{2.025f, 0.025f, 0.025f}}), {0.025, 0.025, 0.025});
  EXPECT_EQ(stats.hits, 0u);
  EXPECT_EQ(stats.rays, 1u);
  // Cut at x = 0.525: voxels 0..9 free, the cut end's voxel 10 not marked (as OctoMap).
  EXPECT_EQ(stats.misses, 10u);
  EXPECT_EQ(map.state({9, 0, 0}), VoxelState::Free);
  EXPECT_EQ(map.state({10, 0, 0}), VoxelState::Unknown);
  EXPECT_EQ(map.state({40, 0, 0}), VoxelState::Unknown);

  s.clear_beyond_max_range = false;
  MetricMap quiet(settings_at_resolution(kRes));
  RayIntegrator ignoring(s);
  const auto none = ignoring.integrate(quiet, cloud({{2.025f, 0.025f, 0.025f}}), {0.025, 0.025, 0.025});
  EXPECT_EQ(none.rays, 0u);
  EXPECT_TRUE(quiet.blocks().empty());
}

TEST(RayIntegrator, TrueEndPointsWhenNotDiscretised) {
  IntegratorSettings s;
  s.discretize = false;
  MetricMap map(settings_at_resolution(kRes));
  RayIntegrator integrator(s);
  const auto stats = integrator.integrate(map, cloud({{0.51f, 0.02f, 0.03f}, {0.54f, 0.03f, 0.02f}}),
                                          {0.025, 0.025, 0.025});
  EXPECT_EQ(stats.rays, 2u);
  EXPECT_EQ(stats.hits, 1u);
  EXPECT_EQ(map.state({10, 0, 0}), VoxelState::Occupied);
}

TEST(RayIntegrator, RejectsAndCountsPointsBeyondTenKilometres) {
  MetricMap map(settings_at_resolution(kRes));
  RayIntegrator integrator;
  PointBuffer pts = cloud({{0.525f, 0.025f, 0.025f}, {10000.5f, 0, 0}, {0, -20000, 0}});
  pts.push_back(std::nanf(""), 0, 0);
  const auto stats = integrator.integrate(map, pts, {0.025, 0.025, 0.025});
  EXPECT_EQ(stats.points_in, 4u);
  EXPECT_EQ(stats.points_rejected, 3u);
  EXPECT_EQ(stats.rays, 1u);
  EXPECT_THROW(integrator.integrate(map, pts, {20000, 0, 0}), Error);
}

// Points a kilometre apart make a scan box far beyond the dense tables'
// limits (1.25 M blocks, 80 M cells at 0.05 m): the scan goes through the
// hash tables, and the rays are walked all the same.
TEST(RayIntegrator, ScanBoxesAKilometreWideUseTheHashTables) {
  MetricMap map(settings_at_resolution(kRes));
  RayIntegrator integrator;
  const PointBuffer pts = cloud({{500.0f, 0.5f, 0.5f}, {-500.0f, -200.0f, 0.5f}, {0.2f, 0.1f, 0.3f}});
  const auto stats = integrator.integrate(map, pts, {0.025, 0.025, 0.025});
  EXPECT_EQ(stats.rays, 3u);
  EXPECT_EQ(stats.dense_walks, 0u);
  EXPECT_EQ(stats.dense_dedupes, 0u);
  EXPECT_GT(stats.voxel_visits, 2 * 10000u);  // both long rays walked cell by cell
  EXPECT_EQ(map.state_at({500.01, 0.5, 0.5}), VoxelState::Occupied);
  EXPECT_EQ(map.state_at({250.02, 0.27, 0.27}), VoxelState::Free);
}

TEST(RayIntegrator, BadLabelThrowsBeforeTouchingTheMap) {
  MetricMap map(settings_at_resolution(kRes));
  RayIntegrator integrator;
  PointBuffer pts = cloud({{0.525f, 0.025f, 0.025f}, {0.3f, 0.2f, 0.1f}});
  pts.labels()[1] = 9;
  try {
    integrator.integrate(map, pts, {0.025, 0.025, 0.025});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidData);
    EXPECT_NE(std::string(e.what()).find("point 1 has label 9"), std::string::npos);
  }
  EXPECT_TRUE(map.blocks().empty());
}

// Labels are checked in parallel per stretch of points; the error names the
// first bad point of the scan, whichever thread found which.
TEST(RayIntegrator, BadLabelErrorNamesTheFirstBadPointAcrossChunks) {
  testing::SyntheticRoom room;
  auto scan = room.frame(0, 1, 256, 192);
  ASSERT_GT(scan.points.size(), 30000u);  // several of pass 1's chunks
  scan.points.labels()[25000] = 6;
  scan.points.labels()[9000] = 9;
  for (const int threads : {1, 2}) {
    tbb::task_arena arena(threads);
    MetricMap map(settings_at_resolution(kRes));
    RayIntegrator integrator;
    arena.execute([&] {
      try {
        integrator.integrate(map, scan.points, scan.origin);
        ADD_FAILURE() << "expected an error";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("point 9000 has label 9"), std::string::npos) << e.what();
      }
    });
    EXPECT_TRUE(map.blocks().empty());
  }
}

TEST(RayIntegrator, HistogramFusionCountsPointsPerClass) {
  MetricMapSettings ms = settings_at_resolution(kRes);
  ms.fusion.fusion = ClassFusion::Histogram;
  MetricMap map(ms);
  RayIntegrator integrator;
  PointBuffer pts = cloud({{0.51f, 0.02f, 0.03f}, {0.52f, 0.03f, 0.02f}, {0.53f, 0.01f, 0.01f}});
  pts.labels()[0] = static_cast<std::uint8_t>(ClassId::Terrain);
  integrator.integrate(map, pts, {0.025, 0.025, 0.025});
  const ClassEvidence e = map.evidence({10, 0, 0});
  EXPECT_EQ(e[static_cast<int>(ClassId::Terrain)], 1);
  EXPECT_EQ(e[static_cast<int>(ClassId::Wall)], 2);
  EXPECT_EQ(map.class_of({10, 0, 0}), ClassId::Wall);
}

TEST(RayIntegrator, FreedVoxelLosesItsClassGradually) {
  MetricMap map(settings_at_resolution(kRes));
  RayIntegrator integrator;
  for (int i = 0; i < 3; ++i) integrator.integrate(map, cloud({{0.275f, 0.025f, 0.025f}}), {0.025, 0.025, 0.025});
  const int wall = static_cast<int>(ClassId::Wall);
  const int before = map.evidence({5, 0, 0})[wall];
  ASSERT_GT(before, 0);
  std::vector<int> seen;
  std::vector<VoxelState> states;
  for (int i = 0; i < 40; ++i) {
    integrator.integrate(map, cloud({{0.775f, 0.025f, 0.025f}}), {0.025, 0.025, 0.025});
    seen.push_back(map.evidence({5, 0, 0})[wall]);
    states.push_back(map.state({5, 0, 0}));
  }
  const auto first_free = std::find(states.begin(), states.end(), VoxelState::Free) - states.begin();
  ASSERT_LT(first_free, 40);
  EXPECT_EQ(seen[0], before);  // misses while still occupied keep the class
  EXPECT_EQ(map.class_of({5, 0, 0}), ClassId::Unknown);  // free voxels carry no class
  // Not at once: evidence remains after the voxel turned free, then fades to none.
  EXPECT_GT(seen[first_free], 0);
  EXPECT_LT(seen[first_free], before);
  EXPECT_EQ(seen.back(), 0);
}

// A plain serial version of the same semantics, for comparison, into dense
// blocks (map gives the resolution and models only).
void reference_integrate(DenseMap& dense, const MetricMap& map, const PointBuffer& pts,
                         const Eigen::Vector3d& origin) {
  const double inv = map.inv_resolution();
  auto less = [](const VoxelKey& a, const VoxelKey& b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); };
  std::map<VoxelKey, ClassObservation, decltype(less)> ends(less);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    auto& o = ends[key_of(pts.x()[i], pts.y()[i], pts.z()[i], inv)];
    ++o.points;
    ++o.counts[pts.labels()[i]];
  }
  std::set<VoxelKey, decltype(less)> free(less);
  const double start[3] = {origin.x() * inv, origin.y() * inv, origin.z() * inv};
  for (const auto& [k, obs] : ends) {
    const double end[3] = {k.x + 0.5, k.y + 0.5, k.z + 0.5};
    walk_ray(start, end, [&](const VoxelKey& v) {
      free.insert(v);
      return true;
    });
  }
  const auto voxel = [&dense](const VoxelKey& k) -> SemanticVoxel& {
    const BlockKey b = block_of(k);
    return dense[{b.x, b.y, b.z}][static_cast<std::size_t>(local_index(k))];
  };
  for (const VoxelKey& k : free) {
    if (ends.count(k)) continue;
    SemanticVoxel& v = voxel(k);
    v.log_odds = map.occupancy().add(v.log_odds, map.occupancy().miss());
    if (map.occupancy().state(v.log_odds) == VoxelState::Free) map.fusion().decay(v.evidence);
  }
  for (const auto& [k, obs] : ends) {
    SemanticVoxel& v = voxel(k);
    v.log_odds = map.occupancy().add(v.log_odds, map.occupancy().hit());
    map.fusion().observe(v.evidence, obs);
  }
}

TEST(RayIntegrator, OneAndTwoThreadsGiveBitIdenticalMapsEqualToTheReference) {
  testing::SyntheticRoom room;
  for (const ClassFusion fusion : {ClassFusion::Bayesian, ClassFusion::Histogram}) {
    MetricMapSettings ms = settings_at_resolution(0.05);
    ms.fusion.fusion = fusion;
    MetricMap one(ms), two(ms);
    DenseMap reference;
    RayIntegrator a, b;
    tbb::task_arena arena1(1), arena2(2);
    for (int f = 0; f < 6; ++f) {
      const auto scan = room.frame(f, 6, 64, 48);
      IntegrationStats s1, s2;
      arena1.execute([&] { s1 = a.integrate(one, scan.points, scan.origin); });
      arena2.execute([&] { s2 = b.integrate(two, scan.points, scan.origin); });
      reference_integrate(reference, one, scan.points, scan.origin);
      EXPECT_EQ(s1.voxel_visits, s2.voxel_visits);
      EXPECT_EQ(s1.misses, s2.misses);
      EXPECT_GT(s1.misses, 1000u);
    }
    EXPECT_TRUE(maps_identical(one, two));
    EXPECT_TRUE(same_as_dense(one, reference));
    EXPECT_GT(one.counts().occupied, 500u);
  }
}

// Scans large enough for several of pass 1's fixed chunks of points, whose
// end voxels and observations are merged across chunks: 1 and 2 threads and
// the serial reference give the same map.
TEST(RayIntegrator, LargeScansSpanningSeveralPointChunksMatchTheReference) {
  testing::SyntheticRoom room;
  MetricMap one(settings_at_resolution(0.05)), two(settings_at_resolution(0.05));
  DenseMap reference;
  RayIntegrator a, b;
  tbb::task_arena arena1(1), arena2(2);
  for (int f = 0; f < 3; ++f) {
    const auto scan = room.frame(f, 3, 256, 192);
    ASSERT_GT(scan.points.size(), 40000u);  // three chunks or more
    IntegrationStats s1, s2;
    arena1.execute([&] { s1 = a.integrate(one, scan.points, scan.origin); });
    arena2.execute([&] { s2 = b.integrate(two, scan.points, scan.origin); });
    reference_integrate(reference, one, scan.points, scan.origin);
    EXPECT_EQ(s1.end_voxels, s2.end_voxels);
    EXPECT_EQ(s1.voxel_visits, s2.voxel_visits);
  }
  EXPECT_TRUE(maps_identical(one, two));
  EXPECT_TRUE(same_as_dense(one, reference));
  EXPECT_GT(one.counts().occupied, 1000u);
}

// Gives every point per-class score channels: a made-up distribution that
// varies from point to point, so the float sums depend on summation order.
void add_class_scores(PointBuffer& points) {
  std::vector<std::size_t> channels;
  for (const ClassInfo& info : kClassTable) channels.push_back(points.add_score(std::string(info.name)));
  for (std::size_t i = 0; i < points.size(); ++i) {
    float total = 0;
    for (std::size_t c = 0; c < channels.size(); ++c) total += 1.0f + static_cast<float>((i * 7 + c * 13) % 17);
    for (std::size_t c = 0; c < channels.size(); ++c) {
      points.score(channels[c])[i] = (1.0f + static_cast<float>((i * 7 + c * 13) % 17)) / total;
    }
  }
}

// The dense scratch (the walk's grid of block masks, the dedupe's table) and
// the hash tables it replaces when a scan's box is too large give the same
// map, with labels or scores, discretised or not, with or without a max range.
TEST(RayIntegrator, DenseAndHashedScratchGiveIdenticalMaps) {
  testing::SyntheticRoom room;
  for (const bool discretize : {true, false}) {
    for (const double max_range : {0.0, 1.5}) {
      for (const bool scores : {false, true}) {
        SCOPED_TRACE(::testing::Message() << "discretize " << discretize << ", max range " << max_range << ", scores "
                                        << scores);
        IntegratorSettings dense;
        dense.discretize = discretize;
        dense.max_range = max_range;
        IntegratorSettings hashed = dense;
        hashed.dense_walk_max_blocks = 0;
        hashed.dense_dedupe_max_cells = 0;
        // Limits below what any of these scans needs: the fallback is chosen per scan by size.
        IntegratorSettings too_small = dense;
        too_small.dense_walk_max_blocks = 1;
        too_small.dense_dedupe_max_cells = 1;
        MetricMap a(settings_at_resolution(kRes)), b(settings_at_resolution(kRes)), c(settings_at_resolution(kRes));
        RayIntegrator ia(dense), ib(hashed), ic(too_small);
        IntegrationStats sa, sb, sc;
        std::size_t scans_with_end_voxels = 0;
        for (int f = 0; f < 4; ++f) {
          auto scan = room.frame(f, 4, 64, 48);
          if (scores) add_class_scores(scan.points);
          const IntegrationStats one = ia.integrate(a, scan.points, scan.origin);
          scans_with_end_voxels += one.end_voxels > 0 ? 1 : 0;
          sa += one;
          sb += ib.integrate(b, scan.points, scan.origin);
          sc += ic.integrate(c, scan.points, scan.origin);
        }
        EXPECT_EQ(sa.dense_walks, 4u);
        EXPECT_EQ(sa.dense_dedupes, scans_with_end_voxels);  // nothing to dedupe when no point is in range
        EXPECT_GE(scans_with_end_voxels, 3u);
        EXPECT_EQ(sb.dense_walks + sb.dense_dedupes + sc.dense_walks + sc.dense_dedupes, 0u);
        EXPECT_EQ(sa.voxel_visits, sb.voxel_visits);
        EXPECT_EQ(sa.misses, sb.misses);
        EXPECT_EQ(sa.hits, sb.hits);
        EXPECT_GT(sa.misses, 1000u);
        EXPECT_TRUE(maps_identical(a, b));
        EXPECT_TRUE(maps_identical(a, c));
      }
    }
  }
}

}  // namespace
}  // namespace sarmap::metric
