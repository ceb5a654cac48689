// Wall bands on exact geometry: a long low band labelled other, or split
// between other and wall, becomes wall (scores moved with it); a box stays
// other, even with sides labelled wall; length is measured along the
// patch's own axis and the limit is where it says; other labels alone are
// touched; bad settings and non-finite points are refused.
#include "engine/semantic/rules/wall_bands.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "tests/semantic/labelled_points.hpp"

namespace sarmap {
namespace {

using testing::add;
using testing::count;
using testing::labelled;
using testing::kOther;
using testing::kWall;
using testing::kTerrain;

// A vertical strip 0.4 m high from (x0, y0) along the horizontal direction
// at `heading_deg`, `length` long, on a 2 cm grid.
void add_strip(PointBuffer& points, double x0, double y0, double heading_deg, double length, std::uint8_t label) {
  const double a = heading_deg * std::numbers::pi / 180.0;
  for (double t = 0.0; t <= length + 1e-9; t += 0.02) {
    for (double z = 0.0; z <= 0.4; z += 0.04) add(points, x0 + t * std::cos(a), y0 + t * std::sin(a), z, label);
  }
}

// A box's top and four sides, `side` metres, corner at (x0, y0).
void add_box(PointBuffer& points, double x0, double y0, double side) {
  for (double u = 0.0; u <= side + 1e-9; u += 0.02) {
    for (double v = 0.0; v <= side + 1e-9; v += 0.02) add(points, x0 + u, y0 + v, side, kOther);
    for (double z = 0.0; z < side; z += 0.04) {
      add(points, x0 + u, y0, z, kOther), add(points, x0 + u, y0 + side, z, kOther);
      add(points, x0, y0 + u, z, kOther), add(points, x0 + side, y0 + u, z, kOther);
    }
  }
}

TEST(WallBands, ALongBandLabelledOtherBecomesWall) {
  PointBuffer points = labelled();
  add_strip(points, 0.005, 0.005, 0.0, 3.0, kOther);
  EXPECT_EQ(label_wall_bands(points, {}), points.size());
  EXPECT_EQ(count(points, kWall), points.size());
}

TEST(WallBands, TheOtherScoreMovesToTheWallScore) {
  PointBuffer points = labelled();
  add_strip(points, 0.005, 0.005, 0.0, 2.0, kOther);
  const std::size_t other = points.add_score("other"), wall = points.add_score("wall");
  for (std::size_t p = 0; p < points.size(); ++p) points.score(other)[p] = 0.6f, points.score(wall)[p] = 0.3f;
  label_wall_bands(points, {});
  for (std::size_t p = 0; p < points.size(); ++p) {
    EXPECT_FLOAT_EQ(points.score(wall)[p], 0.9f) << p;
    EXPECT_FLOAT_EQ(points.score(other)[p], 0.0f) << p;
  }
}

TEST(WallBands, BoxesStayOther) {
  PointBuffer points = labelled();
  add_box(points, 0.005, 0.005, 0.6);
  add_box(points, 1.0, 0.005, 0.6);  // a second box 0.4 m away is another patch
  EXPECT_EQ(label_wall_bands(points, {}), 0u);
  EXPECT_EQ(count(points, kOther), points.size());
}

TEST(WallBands, LengthIsMeasuredAlongThePatch) {
  // 0.9 m at 45 degrees: 7 columns (0.7 m) along x and along y, 0.9 m along itself.
  PointBuffer diagonal = labelled();
  add_strip(diagonal, 0.005, 0.005, 45.0, 0.9, kOther);
  EXPECT_EQ(label_wall_bands(diagonal, {}), diagonal.size());
}

TEST(WallBands, TheLimitIsWhereItSays) {
  // Columns of 10 cm: a strip over 7 columns is 0.7 m, over 8 it is 0.8 m.
  PointBuffer short_strip = labelled();
  add_strip(short_strip, 0.005, 0.005, 0.0, 0.68, kOther);
  EXPECT_EQ(label_wall_bands(short_strip, {}), 0u);
  PointBuffer long_strip = labelled();
  add_strip(long_strip, 0.005, 0.005, 0.0, 0.78, kOther);
  EXPECT_EQ(label_wall_bands(long_strip, {}), long_strip.size());
  WallBandSettings shorter;
  shorter.min_length = 0.7;
  EXPECT_EQ(label_wall_bands(short_strip, shorter), short_strip.size());
}

TEST(WallBands, ABandSplitBetweenWallAndOtherBecomesWall) {
  // One band along x: 0.5 m labelled other, then 1.5 m labelled wall.
  PointBuffer points = labelled();
  add_strip(points, 0.005, 0.005, 0.0, 0.5, kOther);
  const std::size_t other = points.size();
  add_strip(points, 0.525, 0.005, 0.0, 1.5, kWall);
  EXPECT_EQ(label_wall_bands(points, {}), other);
  EXPECT_EQ(count(points, kWall), points.size());
  // The other stretch alone is box-sized.
  PointBuffer alone = labelled();
  add_strip(alone, 0.005, 0.005, 0.0, 0.5, kOther);
  EXPECT_EQ(label_wall_bands(alone, {}), 0u);
}

TEST(WallBands, ABoxWithSidesLabelledWallStaysOther) {
  PointBuffer points = labelled();
  add_box(points, 0.005, 0.005, 0.6);
  // The network called two of its sides wall.
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (points.y()[p] < 0.01f || points.x()[p] < 0.01f) points.labels()[p] = kWall;
  }
  const std::size_t other = count(points, kOther);
  ASSERT_GT(other, 0u);
  EXPECT_EQ(label_wall_bands(points, {}), 0u);
  EXPECT_EQ(count(points, kOther), other);
}

TEST(WallBands, OnlyOtherLabelsAreTouched) {
  PointBuffer points = labelled();
  add_strip(points, 0.005, 0.005, 0.0, 3.0, kTerrain);
  add_strip(points, 0.005, 1.005, 0.0, 3.0, kWall);
  EXPECT_EQ(label_wall_bands(points, {}), 0u);
  EXPECT_EQ(count(points, kTerrain), points.size() / 2);
}

TEST(WallBands, DisabledOrUnlabelledChangesNothing) {
  PointBuffer points = labelled();
  add_strip(points, 0.005, 0.005, 0.0, 3.0, kOther);
  WallBandSettings off;
  off.enabled = false;
  EXPECT_EQ(label_wall_bands(points, off), 0u);
  PointBuffer bare;
  bare.push_back(0.0f, 0.0f, 0.0f);
  EXPECT_EQ(label_wall_bands(bare, {}), 0u);
  PointBuffer empty = labelled();
  EXPECT_EQ(label_wall_bands(empty, {}), 0u);
}

TEST(WallBands, RefusesBadSettingsAndNonFinitePoints) {
  const auto refused = [](auto change) {
    WallBandSettings s;
    change(s);
    EXPECT_THROW(validate(s), Error);
    PointBuffer points = labelled();
    EXPECT_THROW(label_wall_bands(points, s), Error);
  };
  refused([](WallBandSettings& s) { s.column = 0.001; });
  refused([](WallBandSettings& s) { s.column = std::numeric_limits<double>::quiet_NaN(); });
  refused([](WallBandSettings& s) { s.min_length = 0.0; });
  refused([](WallBandSettings& s) { s.min_length = std::numeric_limits<double>::infinity(); });

  PointBuffer points = labelled();
  add(points, 0.0, 0.0, 0.0, kWall);
  add(points, 0.1, 0.0, std::numeric_limits<double>::infinity(), kWall);
  try {
    label_wall_bands(points, {});
    FAIL() << "an infinite point was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 1 is not finite"), std::string::npos) << e.what();
  }
}

TEST(WallBands, PointsBeyondTheGridAreLeftAlone) {
  PointBuffer points = labelled();
  add_strip(points, 5.0e6, 0.0, 90.0, 3.0, kOther);
  EXPECT_EQ(label_wall_bands(points, {}), 0u);
}

}  // namespace
}  // namespace sarmap
