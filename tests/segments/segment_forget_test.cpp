// SegmentMap::forget: the points a bounded map lets go of leave every list
// that names them, the segments that held them are re-derived from the points
// they keep, and what is kept still loads, saves and grows as before.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/flat_key_index.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/segments/plane_moments.hpp"
#include "engine/segments/segment_map.hpp"
#include "tests/segments/segment_map_probes.hpp"
#include "tests/segments/synthetic_surfaces.hpp"

namespace sarmap::segments {
namespace {

using testing::small_arena;
using testing::stripes;

std::vector<PointBuffer> scans(double noise = 0.003) { return stripes(small_arena(), 6, 0.02, noise, 3); }

Eigen::Vector3d origin_of(const PointBuffer& scan) { return {scan.bounds().min.x() + 0.5, 1.5, 0.6}; }

SegmentMap mapped(const std::vector<PointBuffer>& all) {
  SegmentMap map;
  for (const PointBuffer& scan : all) map.integrate(scan, origin_of(scan));
  return map;
}

using testing::pending_total;
using testing::state_of;

// Loading validates every stored index against the points: a renumbering
// that missed a list fails here.
SegmentMap reloaded(const SegmentMap& map) {
  SegmentMap copy;
  const std::string bytes = state_of(map);
  StateReader in(bytes, "forget test");
  copy.load_state(in);
  in.expect_end();
  return copy;
}

// The plane and centroid a segment reports are those of its members, fitted
// afresh here in double precision.
void expect_fits_its_members(const SegmentMap& map, const Segment& s) {
  const std::vector<Eigen::Vector3f> members = map.member_points(s.id);
  ASSERT_EQ(members.size(), s.inliers) << "segment " << s.id;
  PlaneMoments moments;
  for (const Eigen::Vector3f& p : members) moments.add(p.cast<double>());
  const PlaneFit fit = fit_plane(moments);
  EXPECT_LT((fit.centroid - s.centroid).norm(), 1e-6) << "segment " << s.id;
  EXPECT_GT(std::abs(fit.plane.normal.dot(s.plane.normal)), 1 - 1e-9) << "segment " << s.id;
}

bool beyond_two_metres(const Eigen::Vector3d& p) { return p.x() > 2.0; }

TEST(SegmentForget, ForgettingNothingChangesNothing) {
  SegmentMap map = mapped(scans());
  const std::string before = state_of(map);
  const SegmentUpdate u = map.forget([](const Eigen::Vector3d&) { return false; });
  EXPECT_EQ(u.points_forgotten, 0u);
  EXPECT_EQ(u.removed, 0u);
  EXPECT_TRUE(state_of(map) == before);
}

TEST(SegmentForget, KeepsOnlyThePointsOutsideTheForgottenRegion) {
  SegmentMap map = mapped(scans());
  const SegmentMap untouched = reloaded(map);
  const std::size_t before = map.point_count();
  const SegmentUpdate u = map.forget(beyond_two_metres);
  ASSERT_GT(u.points_forgotten, 0u);
  EXPECT_EQ(map.point_count(), before - u.points_forgotten);
  std::size_t untouched_segments = 0;
  for (const Segment* s : map.segments()) {
    SCOPED_TRACE("segment " + std::to_string(s->id));
    for (const Eigen::Vector3f& p : map.member_points(s->id)) EXPECT_LE(p.x(), 2.0f);
    EXPECT_LE(s->max.x(), 2.0);
    expect_fits_its_members(map, *s);
    // A segment wholly on the kept side keeps its id and its every figure.
    const Segment* old = untouched.find(s->id);
    ASSERT_NE(old, nullptr);
    if (old->max.x() <= 2.0) {
      ++untouched_segments;
      EXPECT_EQ(s->plane.normal, old->plane.normal);
      EXPECT_EQ(s->centroid, old->centroid);
      EXPECT_EQ(s->rectangle.center, old->rectangle.center);
      EXPECT_EQ(s->area_m2, old->area_m2);
    }
  }
  EXPECT_GT(untouched_segments, 0u);  // the left platform at least
  // The right platform (x 2.5 to 3.5) and the right wall's part (2.3 to 4) are gone.
  for (const Segment* old : untouched.segments()) {
    if (old->min.x() > 2.0) {
      EXPECT_EQ(map.find(old->id), nullptr) << "segment " << old->id;
    }
  }
  // The floor straddles the cut: it stays, cut back to x <= 2.
  const std::vector<const Segment*> floors = map.of_class(ClassId::Terrain);
  ASSERT_FALSE(floors.empty());
  EXPECT_GT(floors.front()->max.x(), 1.9);
}

TEST(SegmentForget, ForgettingEverythingEmptiesTheMapAndItGrowsBackTheSame) {
  const std::vector<PointBuffer> all = scans(0.0);
  SegmentMap map = mapped(all);
  const SegmentMap fresh = mapped(all);
  const SegmentUpdate u = map.forget([](const Eigen::Vector3d&) { return true; });
  EXPECT_EQ(u.points_forgotten, fresh.point_count());
  EXPECT_EQ(map.size(), 0u);
  EXPECT_EQ(map.point_count(), 0u);
  EXPECT_EQ(pending_total(map), 0u);
  EXPECT_EQ(u.removed, fresh.size());
  // Seen again, the same surfaces come back (under new ids).
  for (const PointBuffer& scan : all) map.integrate(scan, origin_of(scan));
  ASSERT_EQ(map.size(), fresh.size());
  EXPECT_EQ(map.point_count(), fresh.point_count());
  for (const Segment* s : fresh.segments()) {
    bool found = false;
    for (const Segment* t : map.of_class(s->label)) {
      found |= (t->centroid - s->centroid).norm() < 0.01 && std::abs(t->area_m2 - s->area_m2) < 0.01 * s->area_m2;
    }
    EXPECT_TRUE(found) << "segment " << s->id << " of class " << static_cast<int>(s->label);
  }
}

TEST(SegmentForget, ARegionSeenAgainIsSegmentedAgain) {
  const std::vector<PointBuffer> all = scans();
  SegmentMap map = mapped(all);
  map.forget(beyond_two_metres);
  for (const PointBuffer& scan : all) map.integrate(scan, origin_of(scan));
  bool right_wall = false, right_platform = false;
  for (const Segment* s : map.segments()) {
    right_wall |= s->label == ClassId::Wall && s->max.x() > 3.9;
    right_platform |= s->label == ClassId::FlatRamp && s->min.x() > 2.4;
    expect_fits_its_members(map, *s);
  }
  EXPECT_TRUE(right_wall);
  EXPECT_TRUE(right_platform);
}

// Random thirds of the points, forgotten between scans: every index stays
// valid (the state reloads), segments fit their members, and a map loaded
// after a forget continues exactly as the one that forgot.
TEST(SegmentForget, RandomForgettingKeepsEveryListValid) {
  const std::vector<PointBuffer> all = scans();
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    SegmentMap map;
    map.integrate(all[0], origin_of(all[0]));
    std::size_t forgotten = 0;
    for (std::size_t k = 0; k < all.size(); ++k) {
      const auto random_third = [&](const Eigen::Vector3d& p) {
        const auto bits = [](double v) { return static_cast<std::uint64_t>(std::llround(v * 1e4)); };
        return mix_key(bits(p.x()) ^ (bits(p.y()) << 21) ^ (bits(p.z()) << 42) ^ (seed << 60) ^ k) % 3 == 0;
      };
      forgotten += map.forget(random_third).points_forgotten;
      SegmentMap copy = reloaded(map);
      for (const Segment* s : map.segments()) expect_fits_its_members(map, *s);
      if (k + 1 < all.size()) {
        map.integrate(all[k + 1], origin_of(all[k + 1]));
        copy.integrate(all[k + 1], origin_of(all[k + 1]));
        EXPECT_TRUE(state_of(map) == state_of(copy)) << "after scan " << k + 1;
      }
      if (::testing::Test::HasFailure()) return;
    }
    EXPECT_GT(forgotten, 1000u);
    EXPECT_GT(map.size(), 0u);
  }
}

}  // namespace
}  // namespace sarmap::segments
