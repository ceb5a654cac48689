// Mapper::merge: the parts of one simulated sequence mapped apart and merged
// give the whole sequence's maps: the metric map exactly where one part saw a
// voxel, the kept points exactly, the segments by the merge rule; a merged
// Mapper takes no more scans and its state loads as a merged one; a Mapper
// carried by a quarter turn and a whole-voxel shift lands exactly; Mappers
// that cannot merge say why.
#include "engine/pipeline/mapper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "engine/core/state_stream.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/simulator.hpp"
#include "tests/pipeline/default_arena.hpp"
#include "tests/pipeline/same_maps.hpp"

namespace sarmap::pipeline {
namespace {

using testing::default_arena;

// The input's own labels, coarse voxels: the test is about merging, not classifying.
MapperConfig merge_config(double voxel = 0.1) {
  MapperConfig config;
  config.voxel = voxel;
  config.semantic_points_voxel = 0.1;
  config.classifier.kind = ClassifierKind::Labels;
  return config;
}

constexpr std::size_t kFrames = 16, kStride = 3;

// Maps frames [from, to) of the default arena's sequence (every kStride-th).
void map_frames(Mapper& mapper, std::size_t from, std::size_t to) {
  static const sim::Simulator simulator(default_arena());
  for (std::size_t f = from; f < to; ++f) {
    Scan scan = simulator.simulate(f * kStride);
    mapper.integrate(scan);
  }
  mapper.finish();
}

// Mappers hold a mutex: they do not move.
std::unique_ptr<Mapper> mapped(std::size_t from, std::size_t to,
                               const MapperConfig& config = merge_config()) {
  auto mapper = std::make_unique<Mapper>(config, sim::sensor_info(default_arena().sensor));
  map_frames(*mapper, from, to);
  return mapper;
}

std::vector<metric::VoxelKey> voxel_keys(const metric::MetricMap& map) {
  std::vector<metric::VoxelKey> keys;
  for (const metric::BlockKey& k : map.blocks().sorted_block_keys()) {
    for (int z = 0; z < metric::kBlockEdge; ++z)
      for (int y = 0; y < metric::kBlockEdge; ++y)
        for (int x = 0; x < metric::kBlockEdge; ++x)
          keys.push_back(
              {k.x * metric::kBlockEdge + x, k.y * metric::kBlockEdge + y, k.z * metric::kBlockEdge + z});
  }
  return keys;
}

metric::SemanticVoxel voxel(const Mapper& m, const metric::VoxelKey& key) {
  return m.metric_map().blocks().voxel(key).value_or(metric::SemanticVoxel{});
}

std::string points_bytes(const Mapper& m) {
  StateWriter out;
  m.semantic_points().save_state(out);
  return out.bytes();
}

std::map<ClassId, double> area_by_class(const Mapper& m) {
  std::map<ClassId, double> area;
  for (const segments::Segment* s : m.segment_map().segments()) area[s->label] += s->area_m2;
  return area;
}

// What merge() throws, or "" when it merges.
std::string merge_error(Mapper& into, Mapper& other) {
  try {
    into.merge(other);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(MapperMerge, TwoHalvesMergedGiveTheWholeSequencesMaps) {
  const auto whole_mapper = mapped(0, kFrames);
  const auto first_mapper = mapped(0, kFrames / 2);
  const auto second_mapper = mapped(kFrames / 2, kFrames);
  const Mapper& whole = *whole_mapper;
  Mapper& first = *first_mapper;
  Mapper& second = *second_mapper;
  const std::size_t second_blocks = second.metric_map().blocks().block_count();
  const MapperMergeCounts counts = first.merge(second);
  EXPECT_TRUE(first.merged());
  EXPECT_GT(counts.metric.blocks_merged, 0u);
  EXPECT_GT(counts.semantic_points_added, 0u);
  EXPECT_EQ(second.metric_map().blocks().block_count(), second_blocks);  // the other side keeps its maps

  // Metric map: exact wherever one half alone knew the voxel.
  std::size_t one_side = 0, both = 0;
  for (const metric::VoxelKey& key : voxel_keys(whole.metric_map())) {
    const metric::SemanticVoxel w = voxel(whole, key), a = voxel(first, key);
    const bool in_second = voxel(second, key).known();
    if (!w.known()) continue;
    if (!in_second) {
      // `first` now holds the merge; before it, only the first half's voxel was there.
      ++one_side;
      EXPECT_EQ(a.log_odds, w.log_odds);
      EXPECT_TRUE(a.evidence == w.evidence);
    } else {
      ++both;
      EXPECT_TRUE(a.known());
    }
  }
  EXPECT_GT(one_side, 1000u);
  EXPECT_GT(both, 1000u);
  EXPECT_EQ(first.metric_map().counts().known, whole.metric_map().counts().known);

  // Kept points: a voxel keeps its first point, and the first half came first.
  EXPECT_TRUE(points_bytes(first) == points_bytes(whole));

  // Segments: the surfaces the whole sequence found (the same number per class, each
  // class's area within 2 %).
  const auto merged_area = area_by_class(first), whole_area = area_by_class(whole);
  ASSERT_EQ(whole_area.size(), 4u);
  for (const auto& [label, area] : whole_area) {
    ASSERT_TRUE(merged_area.count(label)) << class_info(label).name;
    EXPECT_EQ(first.segment_map().of_class(label).size(), whole.segment_map().of_class(label).size())
        << class_info(label).name;
    EXPECT_NEAR(merged_area.at(label), area, 0.02 * area) << class_info(label).name;
  }
  // The topological map is rebuilt on them.
  const double nodes = static_cast<double>(whole.topo_map().nodes().size());
  EXPECT_GT(nodes, 10);
  EXPECT_NEAR(static_cast<double>(first.topo_map().nodes().size()), nodes, 0.2 * nodes);
  EXPECT_EQ(first.profile().scan_count(), whole.profile().scan_count());
}

// Another robot's map in a frame turned a quarter and shifted by whole
// voxels: merged into an empty Mapper, every voxel, kept point and surface
// lands where the transform says.
TEST(MapperMerge, AMapperCarriedByAKnownTransformLandsWhereItSays) {
  const auto source = mapped(0, kFrames / 2);
  const Pose turn(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                  Eigen::Vector3d(3.0, -2.0, 0.5));
  Mapper merged(merge_config(), sim::sensor_info(default_arena().sensor));
  merged.merge(*source, turn);
  const metric::MetricMap& from = source->metric_map();
  const metric::MetricMap& to = merged.metric_map();
  EXPECT_EQ(to.counts().known, from.counts().known);
  for (const metric::VoxelKey& key : voxel_keys(from)) {
    const metric::SemanticVoxel v = voxel(*source, key);
    if (!v.known()) continue;
    const Eigen::Vector3d c = turn * from.center_of(key);
    const metric::SemanticVoxel w = voxel(merged, metric::key_of(c.x(), c.y(), c.z(), to.inv_resolution()));
    ASSERT_EQ(w.log_odds, v.log_odds);
    ASSERT_TRUE(w.evidence == v.evidence);
  }
  // The kept points, one by one.
  const PointBuffer& points = source->semantic_points();
  ASSERT_EQ(merged.semantic_points().size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p = turn * Eigen::Vector3d(points.x()[i], points.y()[i], points.z()[i]);
    const PointBuffer& moved = merged.semantic_points();
    ASSERT_NEAR(moved.x()[i], p.x(), 1e-5);
    ASSERT_NEAR(moved.y()[i], p.y(), 1e-5);
    ASSERT_NEAR(moved.z()[i], p.z(), 1e-5);
    ASSERT_EQ(moved.labels()[i], points.labels()[i]);
  }
  // The surfaces: as many per class, the same areas, turned normals.
  const auto source_area = area_by_class(*source), merged_area = area_by_class(merged);
  ASSERT_EQ(merged_area.size(), source_area.size());
  for (const auto& [label, area] : source_area) {
    EXPECT_EQ(merged.segment_map().of_class(label).size(), source->segment_map().of_class(label).size())
        << class_info(label).name;
    EXPECT_NEAR(merged_area.at(label), area, 0.02 * area) << class_info(label).name;
  }
  EXPECT_GT(merged.topo_map().nodes().size(), 5u);
}

TEST(MapperMerge, MergesOfMergesGiveTheSameKeptPointsAsOneMapper) {
  // A tree reduction of four quarters, as sarmap.distributed does.
  const auto whole = mapped(0, kFrames);
  const auto q1 = mapped(0, 4), q2 = mapped(4, 8), q3 = mapped(8, 12), q4 = mapped(12, 16);
  q1->merge(*q2);
  q3->merge(*q4);
  q1->merge(*q3);
  EXPECT_TRUE(points_bytes(*q1) == points_bytes(*whole));
  EXPECT_EQ(q1->metric_map().counts().known, whole->metric_map().counts().known);
  EXPECT_EQ(q1->profile().scan_count(), kFrames);
}

TEST(MapperMerge, AMergedMapperTakesNoMoreScans) {
  const auto first_mapper = mapped(0, 2), second_mapper = mapped(2, 4);
  Mapper& first = *first_mapper;
  Mapper& second = *second_mapper;
  first.merge(second);
  static const sim::Simulator simulator(default_arena());
  Scan scan = simulator.simulate(12);
  EXPECT_THROW(first.integrate(scan), Error);
  EXPECT_THROW(first.integrate_stream(
                   0, [](std::size_t, Scan&) { return false; }, [](StreamedScan&) {}),
               Error);
  const std::size_t known = first.metric_map().counts().known;
  first.finish();  // nothing left to finish
  EXPECT_EQ(first.metric_map().counts().known, known);
  // The side merged in goes on mapping.
  EXPECT_NO_THROW(second.integrate(scan));
}

TEST(MapperMerge, AMergedMappersStateLoadsAsAMergedMapper) {
  // What a merge on another process needs: the merged maps travel as state.
  const auto first = mapped(0, 2), second = mapped(2, 4);
  first->merge(*second);
  StateWriter out;
  first->save_state(out);
  Mapper loaded(merge_config(), sim::sensor_info(default_arena().sensor));
  const std::string bytes = out.bytes();
  StateReader in(bytes, "merged state");
  loaded.load_state(in);
  EXPECT_TRUE(loaded.merged());
  expect_same_maps(loaded, *first);
  static const sim::Simulator simulator(default_arena());
  Scan scan = simulator.simulate(12);
  EXPECT_THROW(loaded.integrate(scan), Error);
  // A merged Mapper's state does not make an unmerged one merged, nor the reverse.
  StateWriter unmerged;
  second->save_state(unmerged);
  const std::string unmerged_bytes = unmerged.bytes();
  StateReader back(unmerged_bytes, "unmerged state");
  loaded.load_state(back);
  EXPECT_FALSE(loaded.merged());
}

TEST(MapperMerge, MappersThatCannotMergeSayWhyAndStayUnchanged) {
  const auto fine_mapper = mapped(0, 2);
  Mapper& fine = *fine_mapper;
  const std::size_t blocks = fine.metric_map().blocks().block_count();
  const auto coarse = mapped(2, 4, merge_config(0.2));
  const std::string resolution = merge_error(fine, *coarse);
  EXPECT_NE(resolution.find("resolution"), std::string::npos) << "merged maps of different resolutions: " << resolution;
  MapperConfig other_points = merge_config();
  other_points.semantic_points_voxel = 0.05;
  const auto dense = mapped(2, 4, other_points);
  const std::string points = merge_error(fine, *dense);
  EXPECT_NE(points.find("0.05 m"), std::string::npos) << "merged maps keeping points at different voxels: " << points;
  EXPECT_NE(points.find("0.1 m"), std::string::npos) << points;
  MapperConfig geometric = merge_config();
  geometric.classifier.kind = ClassifierKind::Geometric;
  const auto guessed = mapped(2, 4, geometric);
  EXPECT_THROW(fine.merge(*guessed), Error);
  EXPECT_THROW(fine.merge(fine), Error);
  EXPECT_FALSE(fine.merged());
  EXPECT_EQ(fine.metric_map().blocks().block_count(), blocks);
  EXPECT_NO_THROW(fine.merge(*mapped(4, 6)));
}

}  // namespace
}  // namespace sarmap::pipeline
