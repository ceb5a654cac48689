// The steep-surface check of inclined-ramp labels on exact planes: a wall
// band labelled ramp becomes wall (or other where other scored higher), real
// ramps and other classes are left alone, the slope limit is where it says,
// and bad settings are refused.
#include "engine/semantic/rules/steep_surface_veto.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "tests/semantic/labelled_points.hpp"

namespace sarmap {
namespace {

using testing::count;
using testing::kInclined;
using testing::kWall;
using testing::kOther;
using testing::kFlat;

// A 1.2 m x 0.45 m patch of the plane through the origin that rises at
// `slope_deg` along x (90: a wall facing x), on a 2 cm grid with 1 cm noise
// across the plane, every point labelled `label`.
PointBuffer plane(double slope_deg, std::uint8_t label, double span = 0.45) {
  PointBuffer points;
  points.enable_labels();
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.01);
  const double a = slope_deg * std::numbers::pi / 180.0;
  for (double u = 0.0; u < span; u += 0.02) {      // up the slope
    for (double v = 0.0; v < 1.2; v += 0.02) {     // along the level direction
      const double across = noise(rng);            // along the plane's normal (-sin a, 0, cos a)
      points.push_back(static_cast<float>(u * std::cos(a) - across * std::sin(a)), static_cast<float>(v),
                       static_cast<float>(u * std::sin(a) + across * std::cos(a)));
      points.labels().back() = label;
    }
  }
  return points;
}

TEST(SteepSurfaceVeto, RampLabelsOnAWallBandBecomeWall) {
  PointBuffer points = plane(90.0, kInclined);
  const std::size_t changed = veto_steep_inclined_ramps(points, {});
  EXPECT_EQ(changed, points.size());
  EXPECT_EQ(count(points, kWall), points.size());
}

TEST(SteepSurfaceVeto, OtherWinsWhereTheNetworkScoredItAboveWall) {
  PointBuffer points = plane(80.0, kInclined);
  const std::size_t ramp = points.add_score("inclined_ramp"), wall = points.add_score("wall"),
                    other = points.add_score("other");
  for (std::size_t p = 0; p < points.size(); ++p) {
    points.score(ramp)[p] = 0.5f;
    points.score(wall)[p] = p % 3 == 0 ? 0.1f : 0.3f;
    points.score(other)[p] = p % 3 == 0 ? 0.4f : 0.2f;
  }
  veto_steep_inclined_ramps(points, {});
  for (std::size_t p = 0; p < points.size(); ++p) {
    ASSERT_EQ(points.labels()[p], p % 3 == 0 ? kOther : kWall) << p;
    // The ramp's score went to the new class, which is now the arg-max.
    EXPECT_EQ(points.score(ramp)[p], 0.0f);
    EXPECT_FLOAT_EQ(points.score(wall)[p], p % 3 == 0 ? 0.1f : 0.8f);
    EXPECT_FLOAT_EQ(points.score(other)[p], p % 3 == 0 ? 0.9f : 0.2f);
  }
}

TEST(SteepSurfaceVeto, RealRampsAndOtherClassesStay) {
  for (double slope : {0.0, 10.0, 25.0, 45.0}) {
    PointBuffer ramp = plane(slope, kInclined);
    EXPECT_EQ(veto_steep_inclined_ramps(ramp, {}), 0u) << slope;
    EXPECT_EQ(count(ramp, kInclined), ramp.size()) << slope;
  }
  PointBuffer flat_on_wall = plane(90.0, kFlat);  // only inclined-ramp labels are checked
  EXPECT_EQ(veto_steep_inclined_ramps(flat_on_wall, {}), 0u);
  EXPECT_EQ(count(flat_on_wall, kFlat), flat_on_wall.size());
}

TEST(SteepSurfaceVeto, TheSlopeLimitIsWhereTheSettingSaysAndCanBeSwitchedOff) {
  PointBuffer below = plane(55.0, kInclined), above = plane(65.0, kInclined);
  EXPECT_EQ(veto_steep_inclined_ramps(below, {}), 0u);
  EXPECT_EQ(veto_steep_inclined_ramps(above, {}), above.size());
  SteepSurfaceVetoSettings lower;
  lower.min_slope_deg = 50.0;
  PointBuffer again = plane(55.0, kInclined);
  EXPECT_EQ(veto_steep_inclined_ramps(again, lower), again.size());
  SteepSurfaceVetoSettings off;
  off.enabled = false;
  PointBuffer wall = plane(90.0, kInclined);
  EXPECT_EQ(veto_steep_inclined_ramps(wall, off), 0u);
  EXPECT_EQ(count(wall, kInclined), wall.size());
}

TEST(SteepSurfaceVeto, TooFewPointsAroundGiveNoVerdict) {
  PointBuffer sparse;
  sparse.enable_labels();
  for (int i = 0; i < 6; ++i) {  // a vertical line of 6 points: fewer than min_points
    sparse.push_back(0.0f, 0.0f, 0.05f * static_cast<float>(i));
    sparse.labels().back() = kInclined;
  }
  EXPECT_EQ(veto_steep_inclined_ramps(sparse, {}), 0u);
  PointBuffer unlabelled;
  unlabelled.push_back(0.0f, 0.0f, 0.0f);
  EXPECT_EQ(veto_steep_inclined_ramps(unlabelled, {}), 0u);
  PointBuffer empty;
  empty.enable_labels();
  EXPECT_EQ(veto_steep_inclined_ramps(empty, {}), 0u);
}

TEST(SteepSurfaceVeto, RefusesBadSettings) {
  PointBuffer points = plane(90.0, kInclined);
  for (double cell : {0.0, 0.005, std::nan("")}) {
    SteepSurfaceVetoSettings s;
    s.cell = cell;
    EXPECT_THROW(veto_steep_inclined_ramps(points, s), Error) << cell;
  }
  for (double slope : {0.0, -10.0, 95.0, std::nan("")}) {
    SteepSurfaceVetoSettings s;
    s.min_slope_deg = slope;
    EXPECT_THROW(veto_steep_inclined_ramps(points, s), Error) << slope;
  }
  EXPECT_EQ(count(points, kInclined), points.size()) << "a refused call changes nothing";
}

}  // namespace
}  // namespace sarmap
