// Wall feet on exact geometry: a floor meeting a wall, the floor's last
// centimetres labelled wall. Those become terrain (scores moved with them);
// the wall above the floor stays wall; the tolerance is where it says and is
// measured from the mean floor, not its lowest point; without terrain around
// nothing changes; bad settings and non-finite points are refused.
#include "engine/semantic/rules/wall_feet.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "tests/semantic/labelled_points.hpp"

namespace sarmap {
namespace {

using testing::add;
using testing::count;
using testing::labelled;
using testing::kWall;
using testing::kTerrain;

// Floor on x in [0, 1) at height 0 with +-3 mm of alternating noise (mean
// 0, lowest point -3 mm), y in [0, 1), on a 2 cm grid, labelled terrain.
void add_floor(PointBuffer& points) {
  int i = 0;
  for (double x = 0.0; x < 0.999; x += 0.02) {
    for (double y = 0.0; y < 0.999; y += 0.02, ++i) add(points, x, y, i % 2 == 0 ? 0.003 : -0.003, kTerrain);
  }
}

// The wall's face at x = 1.0, from 2 cm up to 0.5 m, labelled wall.
std::size_t add_wall(PointBuffer& points) {
  std::size_t added = 0;
  for (double y = 0.0; y < 0.999; y += 0.02) {
    for (double z = 0.02; z <= 0.5; z += 0.02, ++added) add(points, 1.0, y, z, kWall);
  }
  return added;
}

// The floor's last 4 cm before the wall, at floor height, labelled wall.
std::size_t add_mislabelled_floor(PointBuffer& points) {
  std::size_t added = 0;
  for (double x = 0.965; x < 0.999; x += 0.01) {
    for (double y = 0.0; y < 0.999; y += 0.02, ++added) add(points, x, y, 0.001, kWall);
  }
  return added;
}

TEST(WallFeet, FloorLabelledWallBecomesTerrainAndTheWallStays) {
  PointBuffer points = labelled();
  add_floor(points);
  const std::size_t floor = points.size();
  const std::size_t wall = add_wall(points);
  const std::size_t foot = add_mislabelled_floor(points);
  ASSERT_GT(foot, 100u);
  EXPECT_EQ(label_wall_feet(points, {}), foot);
  EXPECT_EQ(count(points, kTerrain), floor + foot);
  EXPECT_EQ(count(points, kWall), wall);
}

TEST(WallFeet, TheWallScoreMovesToTheTerrainScore) {
  PointBuffer points = labelled();
  add_floor(points);
  const std::size_t floor = points.size();
  add_mislabelled_floor(points);
  const std::size_t wall = points.add_score("wall"), terrain = points.add_score("terrain");
  for (std::size_t p = floor; p < points.size(); ++p) points.score(wall)[p] = 0.55f, points.score(terrain)[p] = 0.4f;
  label_wall_feet(points, {});
  for (std::size_t p = floor; p < points.size(); ++p) {
    EXPECT_FLOAT_EQ(points.score(terrain)[p], 0.95f) << p;
    EXPECT_FLOAT_EQ(points.score(wall)[p], 0.0f) << p;
  }
}

TEST(WallFeet, TheToleranceIsAboveTheMeanFloor) {
  // The floor's mean is 0 (its lowest point -3 mm): 4 mm up is within the
  // 5 mm tolerance, 6 mm up is not, until the tolerance is 7 mm.
  PointBuffer points = labelled();
  add_floor(points);
  add(points, 0.5, 0.5, 0.004, kWall);
  add(points, 0.5, 0.52, 0.006, kWall);
  PointBuffer again = points;
  EXPECT_EQ(label_wall_feet(points, {}), 1u);
  EXPECT_EQ(points.labels()[points.size() - 2], kTerrain);
  EXPECT_EQ(points.labels()[points.size() - 1], kWall);
  WallFootSettings wider;
  wider.tolerance = 0.007;
  EXPECT_EQ(label_wall_feet(again, wider), 2u);
}

TEST(WallFeet, WithoutTerrainAroundNothingChanges) {
  // Wall labels at floor height with terrain only beyond the neighbouring
  // columns (0.3 m away), then with fewer terrain points than the minimum.
  PointBuffer points = labelled();
  for (double y = 0.0; y < 0.5; y += 0.02) add(points, 0.05, y, 0.0, kWall);
  for (double y = 0.0; y < 0.5; y += 0.02) add(points, 0.35, y, 0.0, kTerrain);
  EXPECT_EQ(label_wall_feet(points, {}), 0u);
  PointBuffer sparse = labelled();
  add(sparse, 0.05, 0.05, 0.0, kWall);
  for (int i = 0; i < 4; ++i) add(sparse, 0.06 + 0.01 * i, 0.05, 0.0, kTerrain);
  EXPECT_EQ(label_wall_feet(sparse, {}), 0u);
  add(sparse, 0.1, 0.05, 0.0, kTerrain);  // the fifth
  EXPECT_EQ(label_wall_feet(sparse, {}), 1u);
}

TEST(WallFeet, DisabledOrUnlabelledChangesNothing) {
  PointBuffer points = labelled();
  add_floor(points);
  add_mislabelled_floor(points);
  WallFootSettings off;
  off.enabled = false;
  EXPECT_EQ(label_wall_feet(points, off), 0u);
  PointBuffer bare;
  bare.push_back(0.0f, 0.0f, 0.0f);
  EXPECT_EQ(label_wall_feet(bare, {}), 0u);
  PointBuffer empty = labelled();
  EXPECT_EQ(label_wall_feet(empty, {}), 0u);
}

TEST(WallFeet, RefusesBadSettingsAndNonFinitePoints) {
  const auto refused = [](auto change) {
    WallFootSettings s;
    change(s);
    EXPECT_THROW(validate(s), Error);
    PointBuffer points = labelled();
    EXPECT_THROW(label_wall_feet(points, s), Error);
  };
  refused([](WallFootSettings& s) { s.column = 0.001; });
  refused([](WallFootSettings& s) { s.column = std::numeric_limits<double>::infinity(); });
  refused([](WallFootSettings& s) { s.tolerance = -0.001; });
  refused([](WallFootSettings& s) { s.tolerance = std::numeric_limits<double>::quiet_NaN(); });
  refused([](WallFootSettings& s) { s.min_floor_points = 0; });

  PointBuffer points = labelled();
  add(points, 0.0, 0.0, 0.0, kWall);
  add(points, 0.1, std::numeric_limits<double>::quiet_NaN(), 0.0, kTerrain);
  try {
    label_wall_feet(points, {});
    FAIL() << "a NaN point was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 1 is not finite"), std::string::npos) << e.what();
  }
}

TEST(WallFeet, PointsBeyondTheGridAreLeftAlone) {
  PointBuffer points = labelled();
  for (int i = 0; i < 10; ++i) add(points, 5.0e6 + 0.01 * i, 0.0, 0.0, kTerrain);
  add(points, 5.0e6, 0.0, 0.0, kWall);
  EXPECT_EQ(label_wall_feet(points, {}), 0u);
}

}  // namespace
}  // namespace sarmap
