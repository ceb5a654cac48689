#include "engine/segments/segment_map.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "engine/core/error.hpp"
#include "tests/segments/synthetic_surfaces.hpp"

namespace sarmap::segments {
namespace {

using testing::add_patch;
using testing::Patch;
using testing::small_arena;
using testing::stripes;

SegmentMap build(const std::vector<PointBuffer>& scans, const SegmentSettings& settings = {}) {
  SegmentMap map(settings);
  for (const PointBuffer& scan : scans) {
    const Eigen::Vector3d origin(scan.bounds().min.x() + 0.5, 1.0, 0.5);
    map.integrate(scan, origin);
  }
  return map;
}

const Segment* near_point(const SegmentMap& map, ClassId label, const Eigen::Vector3d& p) {
  for (const Segment* s : map.of_class(label)) {
    if (std::abs(s->plane.distance(p)) < 0.02 && s->covers(p, 0.05)) return s;
  }
  return nullptr;
}

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180 / std::numbers::pi;
}

TEST(SegmentMap, SmallArenaGivesOneSegmentPerSurface) {
  const SegmentMap map = build(stripes(small_arena(), 6));
  EXPECT_EQ(map.of_class(ClassId::Terrain).size(), 1u);
  EXPECT_EQ(map.of_class(ClassId::Wall).size(), 2u);      // the doorway splits the wall
  EXPECT_EQ(map.of_class(ClassId::FlatRamp).size(), 2u);  // two platforms at one height stay two
  const Segment* floor = near_point(map, ClassId::Terrain, {2, 1.5, 0});
  ASSERT_NE(floor, nullptr);
  EXPECT_LT(angle_deg(floor->plane.normal, Eigen::Vector3d::UnitZ()), 0.01);
  EXPECT_NEAR(floor->plane.offset, 0.0, 1e-4);
  EXPECT_NEAR(floor->area_m2, 12.0, 0.05);
  EXPECT_NEAR(floor->rectangle.half_extents[0], 2.0, 0.01);
  EXPECT_NEAR(floor->rectangle.half_extents[1], 1.5, 0.01);
  EXPECT_NEAR(floor->slope_deg, 0.0, 0.01);
  const Segment* left = near_point(map, ClassId::Wall, {0.7, 2.95, 0.6});
  const Segment* right = near_point(map, ClassId::Wall, {3.0, 2.95, 0.6});
  ASSERT_NE(left, nullptr);
  ASSERT_NE(right, nullptr);
  EXPECT_NE(left->id, right->id);
  // Seen from y = 1: the walls' normals face -y, out of the solid towards the sensor.
  EXPECT_LT(angle_deg(left->plane.normal, -Eigen::Vector3d::UnitY()), 0.01);
  EXPECT_NEAR(left->plane.distance({0, 2.95, 0}), 0.0, 1e-4);
  EXPECT_NEAR(left->slope_deg, 90.0, 0.01);
  EXPECT_NEAR(left->rectangle.half_extents[0], 0.75, 0.01);
  EXPECT_NEAR(left->rectangle.half_extents[1], 0.6, 0.01);
  EXPECT_NEAR(right->max.x(), 4.0, 1e-3);
  EXPECT_NEAR(right->min.x(), 2.3, 0.025);
  // Platforms are never the floor, and the floor is not under their tops.
  const Segment* top = near_point(map, ClassId::FlatRamp, {3, 1, 0.3});
  ASSERT_NE(top, nullptr);
  EXPECT_NEAR(top->plane.offset, -0.3, 1e-4);
  EXPECT_EQ(map.under({3, 1, 0.5}, 1.0), top);
  EXPECT_EQ(map.under({3, 1, 0.25}, 1.0), floor);  // below the top by more than the inlier distance
  EXPECT_EQ(map.under({2, 2.5, 0.4}, 1.0), floor);
  EXPECT_EQ(map.under({2, 2.5, 0.4}, 0.2), nullptr);
  EXPECT_EQ(map.under({6, 2.5, 0.4}, 1.0), nullptr);
  std::size_t inliers = 0;
  for (const Segment* s : map.segments()) inliers += s->inliers;
  EXPECT_EQ(inliers, map.point_count());  // no point left over on exact surfaces
}

TEST(SegmentMap, NoisySurfacesKeepTheirPlanes) {
  const SegmentMap map = build(stripes(small_arena(), 6, 0.02, 0.005));
  const Segment* floor = near_point(map, ClassId::Terrain, {2, 1.5, 0});
  ASSERT_NE(floor, nullptr);
  EXPECT_EQ(map.of_class(ClassId::Terrain).size(), 1u);
  EXPECT_EQ(map.of_class(ClassId::Wall).size(), 2u);
  EXPECT_LT(angle_deg(floor->plane.normal, Eigen::Vector3d::UnitZ()), 0.5);
  EXPECT_NEAR(floor->plane.offset, 0.0, 0.002);
  EXPECT_NEAR(floor->thickness, std::sqrt(12.0) * 0.005, 0.004);
}

TEST(SegmentMap, IdsStayAndTheLowerIdSurvivesAMerge) {
  // Two far ends of one wall first, then the middle that joins them.
  SegmentMap map;
  PointBuffer left, right, middle;
  add_patch(left, {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, ClassId::Wall}, 0.02);
  add_patch(right, {{2, 0, 0}, {1, 0, 0}, {0, 0, 1}, ClassId::Wall}, 0.02);
  add_patch(middle, {{0.9, 0, 0}, {1.2, 0, 0}, {0, 0, 1}, ClassId::Wall}, 0.02);
  map.integrate(left, {0.5, -2, 0.5});
  map.integrate(right, {2.5, -2, 0.5});
  ASSERT_EQ(map.size(), 2u);
  const std::uint32_t a = map.segments()[0]->id, b = map.segments()[1]->id;
  const SegmentUpdate u = map.integrate(middle, {1.5, -2, 0.5});
  ASSERT_EQ(map.size(), 1u);
  EXPECT_GE(u.merged, 1u);
  EXPECT_EQ(map.segments()[0]->id, std::min(a, b));
  EXPECT_EQ(map.resolve(std::max(a, b)), std::min(a, b));
  EXPECT_NEAR(map.segments()[0]->rectangle.half_extents[0], 1.5, 0.01);
  EXPECT_FALSE(map.merges().empty());
}

TEST(SegmentMap, ReclassifiedRegionIsReDerivedAsAFreshBuildWouldBe) {
  const auto scans = stripes(small_arena(), 6);
  SegmentMap map = build(scans);
  // The platform at x 2.5..3.5 turns out to be terrain-coloured clutter: class other.
  PointBuffer revised;
  add_patch(revised, {{2.5, 0.5, 0.3}, {1, 0, 0}, {0, 1, 0}, ClassId::Other}, 0.02);
  const SegmentUpdate u = map.reclassify(revised);
  EXPECT_GE(u.removed, 1u);
  EXPECT_EQ(map.of_class(ClassId::FlatRamp).size(), 1u);
  EXPECT_EQ(near_point(map, ClassId::FlatRamp, {3, 1, 0.3}), nullptr);
  // Half a wall relabelled as other: the wall segment shrinks to what is left.
  PointBuffer half_wall;
  add_patch(half_wall, {{2.3, 2.95, 0}, {0.8, 0, 0}, {0, 0, 1.2}, ClassId::Other}, 0.02);
  map.reclassify(half_wall);
  const Segment* right = near_point(map, ClassId::Wall, {3.6, 2.95, 0.6});
  ASSERT_NE(right, nullptr);
  EXPECT_GT(right->min.x(), 3.09);
  EXPECT_EQ(near_point(map, ClassId::Wall, {2.5, 2.95, 0.6}), nullptr);

  // The same labels from the start give the same segments.
  auto patches = small_arena();
  patches[3].label = ClassId::Other;
  patches[2] = {{3.1, 2.95, 0}, {0.9, 0, 0}, {0, 0, 1.2}, ClassId::Wall};
  patches.push_back({{2.3, 2.95, 0}, {0.78, 0, 0}, {0, 0, 1.2}, ClassId::Other});
  const SegmentMap fresh = build(stripes(patches, 6));
  ASSERT_EQ(fresh.size(), map.size());
  for (ClassId c : {ClassId::Terrain, ClassId::Wall, ClassId::FlatRamp}) {
    const auto a = map.of_class(c), b = fresh.of_class(c);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_LT((a[i]->centroid - b[i]->centroid).norm(), 0.03);
      EXPECT_NEAR(a[i]->area_m2, b[i]->area_m2, 0.06 * b[i]->area_m2);
    }
  }
}

TEST(SegmentMap, SameSegmentsOnOneAndTwoThreads) {
  const auto scans = stripes(small_arena(), 5, 0.02, 0.005);
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return build(scans);
  };
  const SegmentMap one = run(1), two = run(2);
  const auto a = one.segments(), b = two.segments();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i]->id, b[i]->id);
    EXPECT_EQ(a[i]->inliers, b[i]->inliers);
    EXPECT_EQ(a[i]->plane.normal, b[i]->plane.normal);
    EXPECT_EQ(a[i]->rectangle.center, b[i]->rectangle.center);
  }
}

TEST(SegmentMap, CloserViewsReplaceFarPoints) {
  SegmentSettings settings;
  settings.max_range = 0;  // the far view is 8 m away
  SegmentMap map(settings);
  PointBuffer far, near;
  add_patch(far, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, ClassId::Terrain}, 0.02, 0.004, 3);
  add_patch(near, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, ClassId::Terrain}, 0.02, 0.0);
  auto exact = [&map] {
    const auto points = map.member_points(map.segments().front()->id);
    return std::count_if(points.begin(), points.end(), [](const Eigen::Vector3f& p) { return p.z() == 0; });
  };
  map.integrate(far, {0.5, -8, 1});
  ASSERT_EQ(map.size(), 1u);
  EXPECT_LT(exact(), 10);
  const SegmentUpdate u = map.integrate(near, {0.5, 0.5, 1});
  EXPECT_GT(u.points_changed, 500u);
  ASSERT_EQ(map.size(), 1u);
  // Voxels the near view hit hold its exact points now (those it missed keep the far ones).
  EXPECT_GE(exact(), static_cast<std::ptrdiff_t>(u.points_changed));
  // A farther view changes nothing.
  EXPECT_EQ(map.integrate(far, {0.5, -8, 1}).points_changed, 0u);
}

TEST(SegmentMap, BadInputIsAClearError) {
  SegmentSettings bad;
  bad.distance_threshold = 0;
  EXPECT_THROW(SegmentMap{bad}, Error);
  bad = {};
  bad.voxel = std::nan("");
  EXPECT_THROW(SegmentMap{bad}, Error);
  SegmentMap map;
  PointBuffer unlabelled;
  unlabelled.push_back(0, 0, 0);
  EXPECT_THROW(map.integrate(unlabelled, Eigen::Vector3d::Zero()), Error);
  PointBuffer nan_point;
  add_patch(nan_point, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, ClassId::Terrain}, 0.1);
  nan_point.y()[3] = std::nanf("");
  try {
    map.integrate(nan_point, Eigen::Vector3d::Zero());
    FAIL() << "NaN accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 3"), std::string::npos) << e.what();
  }
  PointBuffer ok;
  add_patch(ok, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, ClassId::Terrain}, 0.1);
  EXPECT_THROW(map.integrate(ok, Eigen::Vector3d(0, std::nan(""), 0)), Error);
}

TEST(SegmentMap, PointsBeyondReachOrRangeAreCountedNotStored) {
  SegmentSettings settings;
  settings.max_range = 0;
  SegmentMap map(settings);
  PointBuffer p;
  p.enable_labels();
  p.push_back(0, 0, 0);
  p.push_back(1e7f, 0, 0);
  p.labels()[0] = p.labels()[1] = static_cast<std::uint8_t>(ClassId::Wall);
  const SegmentUpdate u = map.integrate(p, Eigen::Vector3d::Zero());
  EXPECT_EQ(u.points_in, 2u);
  EXPECT_EQ(u.points_rejected, 1u);
  EXPECT_EQ(map.point_count(), 1u);
  SegmentMap near_only;  // max_range 3 m by default
  p.x()[1] = 3.5f;
  const SegmentUpdate v = near_only.integrate(p, Eigen::Vector3d::Zero());
  EXPECT_EQ(v.points_far, 1u);
  EXPECT_EQ(near_only.point_count(), 1u);
}

}  // namespace
}  // namespace sarmap::segments
