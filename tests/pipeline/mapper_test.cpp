// The pipeline's Mapper on synthetic scans: stages and counters in the
// profile, the labels classifier, and one kept semantic point per voxel (the
// first, on any number of threads).
#include "engine/pipeline/mapper.hpp"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/metric/voxel_key.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap::pipeline {
namespace {

TEST(Mapper, RunsTheStagesAndProfilesThem) {
  MapperConfig config;
  config.voxel = 0.1;
  config.semantic_points_voxel = 0.1;
  config.classifier.kind = pipeline::ClassifierKind::Labels;
  SensorInfo sensor;
  sensor.max_range = 4.0;
  Mapper mapper(config, sensor);
  EXPECT_DOUBLE_EQ(mapper.max_range(), 4.0);
  testing::SyntheticRoom room;
  std::size_t points = 0;
  for (int f = 0; f < 3; ++f) {
    auto r = room.frame(f, 3, 160, 120);
    Scan scan;
    scan.points = r.points;
    scan.points.push_back(std::nanf(""), 0, 0);  // dropped by preprocess
    scan.origin = r.origin;
    points += scan.points.size();
    mapper.integrate(scan);
  }
  const StageProfile& p = mapper.profile();
  EXPECT_EQ(p.scan_count(), 3u);
  EXPECT_DOUBLE_EQ(p.counter("preprocess", "points_in"), static_cast<double>(points));
  EXPECT_DOUBLE_EQ(p.counter("preprocess", "points_out"), static_cast<double>(points - 3));
  EXPECT_DOUBLE_EQ(p.counter("classify", "points"), static_cast<double>(points - 3));
  EXPECT_GT(p.counter("metric", "rays"), 0.0);
  EXPECT_GT(p.counter("metric", "voxel_visits"), p.counter("metric", "rays"));
  EXPECT_DOUBLE_EQ(p.counter("metric", "scans_hashed_walk"), 0.0);
  EXPECT_GT(mapper.metric_map().counts().occupied, 100u);
  // Memory after each scan: the map's as it counts it, the integrator's scratch apart.
  const StageProfile::LevelStats map_bytes = p.level("metric", "map_bytes");
  EXPECT_EQ(map_bytes.scans, 3u);
  EXPECT_EQ(map_bytes.last, static_cast<double>(mapper.metric_map().memory_bytes()));
  EXPECT_EQ(map_bytes.max, map_bytes.last);  // an unbounded map only grows
  EXPECT_GT(p.level("metric", "integrator_scratch_bytes").last, 0.0);
  EXPECT_EQ(p.level("classify", "point_map_bytes").scans, 0u);  // the labels classifier keeps no point map
  // One kept point per 0.1 m voxel, its label carried as prediction and ground truth.
  const PointBuffer& kept = mapper.semantic_points();
  ASSERT_GT(kept.size(), 100u);
  ASSERT_TRUE(kept.has_gt_labels());
  std::set<std::uint64_t> voxels;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    EXPECT_EQ(kept.labels()[i], kept.gt_labels()[i]);
    voxels.insert(metric::pack(metric::key_of(kept.x()[i], kept.y()[i], kept.z()[i], 10.0)));
  }
  EXPECT_EQ(voxels.size(), kept.size());
  EXPECT_LT(kept.size(), points / 4);
  // Their own stage: the points kept, and their bytes beside the metric map's.
  EXPECT_DOUBLE_EQ(p.counter("semantic_points", "points_kept"), static_cast<double>(kept.size()));
  const StageProfile::LevelStats kept_bytes = p.level("semantic_points", "bytes");
  EXPECT_EQ(kept_bytes.scans, 3u);
  EXPECT_EQ(kept_bytes.last, static_cast<double>(mapper.semantic_points_bytes()));
  EXPECT_GE(mapper.semantic_points_bytes(), kept.size() * (3 * sizeof(float) + 2) + mapper.semantic_points().size() * 8);
}

// The kept points against a plain reference: every point in input order,
// kept when it is the first in its voxel. Scans of several thousand points
// (so that the lookups run in pieces on several threads), points repeated
// back to back, voxels shared between scans, on one thread and on four.
TEST(Mapper, KeepsTheFirstPointOfEachVoxelOnAnyThreadCount) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f);
  std::vector<PointBuffer> scans(3);
  for (PointBuffer& points : scans) {
    points.enable_labels();
    points.enable_gt_labels();
    while (points.size() < 10000) {
      const float x = coordinate(rng), y = coordinate(rng), z = coordinate(rng) + 1.5f;
      const int copies = rng() % 4 == 0 ? 2 : 1;
      for (int k = 0; k < copies; ++k) {
        points.push_back(x, y, z);
        points.labels().back() = points.gt_labels().back() = static_cast<std::uint8_t>(ClassId::Wall);
      }
    }
  }
  std::vector<std::pair<std::size_t, std::size_t>> expected;  // (scan, point)
  std::set<std::uint64_t> voxels;
  for (std::size_t s = 0; s < scans.size(); ++s) {
    for (std::size_t i = 0; i < scans[s].size(); ++i) {
      const auto key = metric::pack(metric::key_of(scans[s].x()[i], scans[s].y()[i], scans[s].z()[i], 1 / 0.1));
      if (voxels.insert(key).second) expected.emplace_back(s, i);
    }
  }
  for (const int threads : {1, 4}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    MapperConfig config;
    config.voxel = 0.1;
    config.semantic_points_voxel = 0.1;
    config.classifier.kind = pipeline::ClassifierKind::Labels;
    Mapper mapper(config, SensorInfo{});
    for (const PointBuffer& points : scans) {
      Scan scan;
      scan.points = points;
      scan.origin = Eigen::Vector3d(0, 0, 1.5);
      mapper.integrate(scan);
    }
    const PointBuffer& kept = mapper.semantic_points();
    ASSERT_EQ(kept.size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      const auto [s, i] = expected[k];
      ASSERT_EQ(kept.x()[k], scans[s].x()[i]) << "kept point " << k;
      ASSERT_EQ(kept.y()[k], scans[s].y()[i]) << "kept point " << k;
      ASSERT_EQ(kept.z()[k], scans[s].z()[i]) << "kept point " << k;
    }
    EXPECT_DOUBLE_EQ(mapper.profile().counter("semantic_points", "points_kept"), static_cast<double>(expected.size()));
  }
}

// Scans whose box is too large for the dense marking grid are counted.
TEST(Mapper, CountsScansWalkedThroughHashTables) {
  MapperConfig config;
  config.voxel = 0.1;
  config.classifier.kind = pipeline::ClassifierKind::Labels;
  config.integrator.dense_walk_max_blocks = 4;  // smaller than any scan of the room at 0.1 m
  Mapper mapper(config, SensorInfo{});
  testing::SyntheticRoom room;
  for (int f = 0; f < 2; ++f) {
    auto r = room.frame(f, 2, 64, 48);
    Scan scan;
    scan.points = r.points;
    scan.origin = r.origin;
    mapper.integrate(scan);
  }
  EXPECT_DOUBLE_EQ(mapper.profile().counter("metric", "scans_hashed_walk"), 2.0);
}

TEST(Mapper, GeometricClassifierLabelsAndKeepsGroundTruth) {
  MapperConfig config;
  config.voxel = 0.1;
  config.semantic_points_voxel = 0.1;
  config.classifier.kind = pipeline::ClassifierKind::Geometric;
  Mapper mapper(config);
  EXPECT_EQ(mapper.classifier().name(), "geometric");
  testing::SyntheticRoom room;
  auto r = room.frame(0, 1, 160, 120);
  Scan scan;
  scan.points = r.points;
  scan.origin = r.origin;
  mapper.integrate(scan);
  // The input's labels survive as ground truth, the predictions are the baseline's own.
  const PointBuffer& kept = mapper.semantic_points();
  ASSERT_GT(kept.size(), 100u);
  ASSERT_TRUE(kept.has_gt_labels());
  std::size_t labelled = 0;
  for (std::size_t i = 0; i < kept.size(); ++i) labelled += kept.labels()[i] != 0;
  EXPECT_GT(labelled, kept.size() / 2);
}

TEST(Mapper, RejectsBadClassifiersAndUnlabelledInput) {
  EXPECT_THROW(classifier_kind_from_name("oracle"), Error);
  EXPECT_EQ(classifier_kind_from_name("geometric"), ClassifierKind::Geometric);
  MapperConfig bogus;
  bogus.classifier.kind = static_cast<ClassifierKind>(7);
  EXPECT_THROW(Mapper{bogus}, Error);
  MapperConfig no_model;  // dgcnn is the default and needs a model file
  EXPECT_THROW(Mapper{no_model}, Error);
  MapperConfig missing;
  missing.classifier.model = "/nonexistent/model.safetensors";
  EXPECT_THROW(Mapper{missing}, Error);
  MapperConfig labels;
  labels.classifier.kind = pipeline::ClassifierKind::Labels;
  Mapper mapper(labels);
  Scan scan;
  scan.points.push_back(1, 1, 1);
  try {
    mapper.integrate(scan);
    FAIL() << "an unlabelled scan must be refused by the labels classifier";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("label"), std::string::npos) << e.what();
  }
}

TEST(Mapper, RefusesBadMapBounds) {
  for (double radius : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    MapperConfig config;
    config.classifier.kind = pipeline::ClassifierKind::Labels;
    config.bounds.keep_radius = radius;
    EXPECT_THROW(Mapper mapper(config), Error);
  }
}

TEST(Mapper, KeepsTheMapWithinItsBoundsBudgetAndRadius) {
  testing::SyntheticRoom room;
  MapperConfig unbounded;
  unbounded.classifier.kind = pipeline::ClassifierKind::Labels;
  MapperConfig bounded = unbounded;
  bounded.bounds.keep_radius = 1.5;
  bounded.bounds.max_blocks = 60;
  Mapper full(unbounded), small(bounded);
  Eigen::Vector3d last_origin;
  for (int f = 0; f < 4; ++f) {
    auto r = room.frame(f, 4, 128, 96);
    Scan a, b;
    a.points = r.points;
    b.points = r.points;
    a.origin = b.origin = last_origin = r.origin;
    full.integrate(a);
    small.integrate(b);
    EXPECT_LE(small.metric_map().blocks().block_count(), 60u);
  }
  ASSERT_GT(full.metric_map().blocks().block_count(), 60u);
  EXPECT_GT(small.blocks_dropped(), 0u);
  EXPECT_GT(small.profile().counter("metric", "blocks_dropped"), 0.0);
  const double edge = 0.05 * metric::kBlockEdge;
  small.metric_map().blocks().for_each_block([&](const metric::BlockKey& k, const auto&) {
    const Eigen::Vector3d c((k.x + 0.5) * edge, (k.y + 0.5) * edge, (k.z + 0.5) * edge);
    EXPECT_LE((c - last_origin).norm(), 1.5 + 1e-9);
  });
  // What is kept near the sensor is mapped as without bounds: the voxels of
  // the block holding the sensor agree.
  const metric::VoxelKey here = *full.metric_map().key_at(last_origin);
  const metric::BlockKey home = metric::block_of(here);
  for (int local = 0; local < metric::kBlockVoxels; ++local) {
    const metric::VoxelKey v = metric::voxel_of(home, local);
    EXPECT_EQ(small.metric_map().state(v), full.metric_map().state(v));
  }
}

// With bounds, the segment stage's points and the kept semantic points follow
// the metric map: after forget_dropped_regions() none lies in a block the
// map no longer holds, and both hold fewer points than without bounds.
TEST(Mapper, BoundedMapForgetsSegmentAndKeptPointsWithItsBlocks) {
  testing::SyntheticRoom room;
  MapperConfig unbounded;
  unbounded.classifier.kind = pipeline::ClassifierKind::Labels;
  MapperConfig bounded = unbounded;
  bounded.bounds.max_blocks = 200;
  Mapper full(unbounded), small(bounded);
  for (int f = 0; f < 6; ++f) {
    auto r = room.frame(f, 6, 128, 96);
    Scan a, b;
    a.points = r.points;
    b.points = r.points;
    a.origin = b.origin = r.origin;
    full.integrate(a);
    small.integrate(b);
  }
  // Passes ran during the scans (each once an eighth of the blocks had gone).
  EXPECT_GT(small.profile().counter("segment", "points_forgotten"), 0.0);
  EXPECT_GT(small.profile().counter("metric", "semantic_points_forgotten"), 0.0);
  small.forget_dropped_regions();
  const metric::MetricMap& map = small.metric_map();
  const auto held = [&](double x, double y, double z) {
    return map.blocks().voxel(metric::key_of(x, y, z, map.inv_resolution())).has_value();
  };
  const PointBuffer& kept = small.semantic_points();
  ASSERT_GT(kept.size(), 0u);
  for (std::size_t i = 0; i < kept.size(); ++i) EXPECT_TRUE(held(kept.x()[i], kept.y()[i], kept.z()[i])) << i;
  for (const segments::Segment* s : small.segment_map().segments()) {
    for (const Eigen::Vector3f& p : small.segment_map().member_points(s->id)) {
      EXPECT_TRUE(held(p.x(), p.y(), p.z())) << "segment " << s->id;
    }
  }
  ASSERT_GT(full.metric_map().blocks().block_count(), 400u);
  EXPECT_LT(kept.size(), full.semantic_points().size());
  EXPECT_LT(small.segment_map().point_count(), full.segment_map().point_count());
  // Forgetting again finds nothing more to forget.
  const double before = small.profile().counter("segment", "points_forgotten");
  small.forget_dropped_regions();
  EXPECT_EQ(small.profile().counter("segment", "points_forgotten"), before);
}

}  // namespace
}  // namespace sarmap::pipeline
