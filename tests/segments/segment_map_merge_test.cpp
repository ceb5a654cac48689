// SegmentMap::merge: two maps of one frame become the map one robot would
// have built, by the scan-by-scan merge rule; a map of another frame, carried
// by a rigid transform, lands where the transform puts it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <Eigen/Geometry>

#include "engine/core/error.hpp"
#include "engine/segments/segment_map.hpp"
#include "tests/segments/synthetic_surfaces.hpp"

namespace sarmap::segments {
namespace {

using testing::add_patch;
using testing::small_arena;
using testing::stripes;

void integrate_stripes(SegmentMap& map, const std::vector<PointBuffer>& scans, std::size_t from,
                       std::size_t to) {
  for (std::size_t s = from; s < to; ++s) {
    map.integrate(scans[s], Eigen::Vector3d(scans[s].bounds().min.x() + 0.5, 1.0, 0.5));
  }
}

std::size_t inliers(const SegmentMap& map) {
  std::size_t n = 0;
  for (const Segment* s : map.segments()) n += s->inliers;
  return n;
}

const Segment* largest(const SegmentMap& map, ClassId label) {
  const auto of = map.of_class(label);
  if (of.empty()) return nullptr;
  return *std::max_element(of.begin(), of.end(),
                           [](const Segment* a, const Segment* b) { return a->area_m2 < b->area_m2; });
}

TEST(SegmentMapMerge, TwoHalvesOfATraverseGiveTheWholeTraversesSegments) {
  const std::vector<PointBuffer> scans = stripes(small_arena(), 6);
  SegmentMap whole, first, second;
  integrate_stripes(whole, scans, 0, 6);
  integrate_stripes(first, scans, 0, 3);
  integrate_stripes(second, scans, 3, 6);
  // Each half alone sees a part of the floor and of the walls.
  ASSERT_LT(largest(first, ClassId::Terrain)->area_m2, 10.0);
  const SegmentUpdate u = first.merge(second);
  EXPECT_GE(u.merged, 1u);
  for (const ClassId c : {ClassId::Terrain, ClassId::Wall, ClassId::FlatRamp}) {
    EXPECT_EQ(first.of_class(c).size(), whole.of_class(c).size()) << class_info(c).name;
  }
  EXPECT_EQ(first.point_count(), whole.point_count());
  EXPECT_EQ(inliers(first), first.point_count());  // every stored point in a segment, as in the whole
  const Segment* floor = largest(first, ClassId::Terrain);
  EXPECT_NEAR(floor->area_m2, largest(whole, ClassId::Terrain)->area_m2, 1e-6);
  EXPECT_NEAR(floor->plane.offset, 0.0, 1e-4);
}

// Another robot's frame, a quarter turn and a shift away: merged into an
// empty map through the transform, every surface comes out where the
// transform puts it, with its area, to within the thinning voxel.
TEST(SegmentMapMerge, AMapInAnotherFrameLandsWhereTheTransformPutsIt) {
  const std::vector<PointBuffer> scans = stripes(small_arena(), 6);
  SegmentMap source, moved;
  integrate_stripes(source, scans, 0, 6);
  const Pose turn(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                  Eigen::Vector3d(5.0, -1.0, 0.2));
  moved.merge(source, turn);
  ASSERT_EQ(moved.size(), source.size());
  // The points move exactly, but this map thins them on its own grid: the
  // test's points lie on voxel edges, which a turn moves to the neighbour
  // (measured: 8.7 % fewer stored points, centroids within 3.1 cm).
  EXPECT_NEAR(static_cast<double>(moved.point_count()), static_cast<double>(source.point_count()),
              0.15 * static_cast<double>(source.point_count()));
  for (const ClassId c : {ClassId::Terrain, ClassId::Wall, ClassId::FlatRamp}) {
    ASSERT_EQ(moved.of_class(c).size(), source.of_class(c).size()) << class_info(c).name;
    const Segment* a = largest(source, c);
    const Segment* b = largest(moved, c);
    EXPECT_NEAR(b->area_m2, a->area_m2, 0.02 * a->area_m2) << class_info(c).name;
    EXPECT_NEAR((b->plane.normal - turn.rotation() * a->plane.normal).norm(), 0.0, 1e-2) << class_info(c).name;
    EXPECT_NEAR((b->centroid - turn * a->centroid).norm(), 0.0, 0.05) << class_info(c).name;
  }
}

TEST(SegmentMapMerge, ASegmentThatContinuesOneHereMergesIntoTheLowerId) {
  // This map holds both ends of a wall; the other map holds its middle.
  SegmentMap here, other;
  PointBuffer left, right, middle;
  add_patch(left, {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, ClassId::Wall}, 0.02);
  add_patch(right, {{2, 0, 0}, {1, 0, 0}, {0, 0, 1}, ClassId::Wall}, 0.02);
  add_patch(middle, {{0.9, 0, 0}, {1.2, 0, 0}, {0, 0, 1}, ClassId::Wall}, 0.02);
  here.integrate(left, {0.5, -2, 0.5});
  here.integrate(right, {2.5, -2, 0.5});
  other.integrate(middle, {1.5, -2, 0.5});
  ASSERT_EQ(here.size(), 2u);
  ASSERT_EQ(other.size(), 1u);
  const std::uint32_t lowest = here.segments()[0]->id;
  here.merge(other);
  ASSERT_EQ(here.size(), 1u);
  EXPECT_EQ(here.segments()[0]->id, lowest);
  EXPECT_NEAR(here.segments()[0]->rectangle.half_extents[0], 1.5, 0.01);
  // The other map is unchanged.
  EXPECT_EQ(other.size(), 1u);
}

TEST(SegmentMapMerge, DisjointMapsKeepEverySegment) {
  SegmentMap here, other;
  PointBuffer wall, floor;
  add_patch(wall, {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, ClassId::Wall}, 0.02);
  add_patch(floor, {{5, 5, 0}, {1, 0, 0}, {0, 1, 0}, ClassId::Terrain}, 0.02);
  here.integrate(wall, {0.5, -2, 0.5});
  other.integrate(floor, {5.5, 5.5, 1.0});
  const Segment* theirs = other.segments()[0];
  const std::size_t points_here = here.point_count();
  here.merge(other);
  ASSERT_EQ(here.size(), 2u);
  ASSERT_EQ(here.of_class(ClassId::Terrain).size(), 1u);
  const Segment* merged = here.of_class(ClassId::Terrain)[0];
  EXPECT_EQ(merged->inliers, theirs->inliers);
  EXPECT_NEAR(merged->area_m2, theirs->area_m2, 1e-9);
  EXPECT_NEAR(merged->plane.offset, theirs->plane.offset, 1e-9);
  EXPECT_EQ(here.point_count(), points_here + other.point_count());
}

TEST(SegmentMapMerge, AnEmptyMapChangesNothingAndTakesEverything) {
  const std::vector<PointBuffer> scans = stripes(small_arena(), 3);
  SegmentMap built, empty;
  integrate_stripes(built, scans, 0, 3);
  const std::size_t segments = built.size(), points = built.point_count();
  built.merge(empty);
  EXPECT_EQ(built.size(), segments);
  EXPECT_EQ(built.point_count(), points);
  empty.merge(built);
  EXPECT_EQ(empty.size(), segments);
  EXPECT_EQ(empty.point_count(), points);
}

TEST(SegmentMapMerge, DifferentThinningOrTheSameMapIsAnErrorNamingBoth) {
  SegmentSettings coarse;
  coarse.voxel = 0.05;
  SegmentMap fine_map, coarse_map(coarse);
  try {
    fine_map.merge(coarse_map);
    FAIL() << "merged maps thinned to different voxels";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    const std::string what = e.what();
    EXPECT_NE(what.find("0.05 m"), std::string::npos) << what;
    EXPECT_NE(what.find("0.025 m"), std::string::npos) << what;
  }
  EXPECT_THROW(fine_map.merge(fine_map), Error);
}

}  // namespace
}  // namespace sarmap::segments
