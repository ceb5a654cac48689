// Ramp side faces on exact geometry: a 20-degree wedge ramp whose deck the
// network labelled inclined ramp and whose vertical side it labelled wall.
// The side becomes ramp (scores moved with it), also when labelled other;
// a wall standing above the ramp, a wall far from it, and walls under a
// steep "deck" or a ridge stay wall; decks are remembered across scans until cleared; bad settings
// and non-finite points are refused.
#include "engine/semantic/rules/ramp_side_faces.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "tests/semantic/labelled_points.hpp"

namespace sarmap {
namespace {

using testing::add;
using testing::count;
using testing::labelled;
using testing::kWall;
using testing::kInclined;

const double kTan20 = std::tan(20.0 * std::numbers::pi / 180.0);

// The deck: x in [0, 1], y in [0, 0.6], rising 20 degrees along x (to
// 0.364 m), on a 2 cm grid with 3 mm noise, labelled inclined ramp.
void add_deck(PointBuffer& points, double slope_deg = 20.0) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.003);
  const double rise = std::tan(slope_deg * std::numbers::pi / 180.0);
  for (double x = 0.0; x <= 1.0; x += 0.02) {
    for (double y = 0.0; y <= 0.6; y += 0.02) add(points, x, y, x * rise + noise(rng), kInclined);
  }
}

// The side under the deck's edge y = 0: the vertical triangle below it,
// kept 3 cm under the deck (the rule's minimum rise), labelled wall.
std::size_t add_side(PointBuffer& points) {
  std::size_t added = 0;
  for (double x = 0.1; x <= 1.0; x += 0.02) {
    for (double z = 0.0; z <= x * kTan20 - 0.03; z += 0.02, ++added) add(points, x, -0.005, z, kWall);
  }
  return added;
}

TEST(RampSideFaces, TheSideUnderADeckBecomesRamp) {
  PointBuffer points = labelled();
  add_deck(points);
  const std::size_t deck = points.size();
  const std::size_t side = add_side(points);
  ASSERT_GT(side, 100u);
  EXPECT_EQ(label_ramp_side_faces(points, {}), side);
  EXPECT_EQ(count(points, kInclined), deck + side);
  EXPECT_EQ(count(points, kWall), 0u);
}

TEST(RampSideFaces, ASideLabelledOtherBecomesRampToo) {
  PointBuffer points = labelled();
  add_deck(points);
  const std::size_t deck = points.size();
  const std::size_t side = add_side(points);
  const std::size_t other = points.add_score("other"), ramp = points.add_score("inclined_ramp");
  for (std::size_t p = deck; p < points.size(); ++p) {
    points.labels()[p] = static_cast<std::uint8_t>(ClassId::Other);
    points.score(other)[p] = 0.6f;
    points.score(ramp)[p] = 0.1f;
  }
  EXPECT_EQ(label_ramp_side_faces(points, {}), side);
  EXPECT_EQ(count(points, kInclined), deck + side);
  for (std::size_t p = deck; p < points.size(); ++p) {
    EXPECT_FLOAT_EQ(points.score(ramp)[p], 0.7f) << p;
    EXPECT_FLOAT_EQ(points.score(other)[p], 0.0f) << p;
  }
}

TEST(RampSideFaces, TheWallScoreMovesToTheRampScore) {
  PointBuffer points = labelled();
  add_deck(points);
  const std::size_t deck = points.size();
  add_side(points);
  const std::size_t wall = points.add_score("wall"), ramp = points.add_score("inclined_ramp");
  for (std::size_t p = deck; p < points.size(); ++p) {
    points.score(wall)[p] = 0.7f;
    points.score(ramp)[p] = 0.2f;
  }
  label_ramp_side_faces(points, {});
  for (std::size_t p = deck; p < points.size(); ++p) {
    EXPECT_FLOAT_EQ(points.score(ramp)[p], 0.9f) << p;
    EXPECT_FLOAT_EQ(points.score(wall)[p], 0.0f) << p;
  }
}

TEST(RampSideFaces, WallsAboveTheRampOrFarFromItStayWall) {
  PointBuffer points = labelled();
  add_deck(points);
  // A wall along the ramp's far edge, seen only above the ramp's top (the
  // ramp hides it below), and a wall 2 m away from the floor up.
  std::size_t walls = 0;
  for (double x = 0.0; x <= 1.0; x += 0.02) {
    for (double z = 0.364 + 0.03; z <= 2.0; z += 0.05, ++walls) add(points, x, 0.62, z, kWall);
  }
  for (double y = 0.0; y <= 1.0; y += 0.02) {
    for (double z = 0.0; z <= 2.0; z += 0.05, ++walls) add(points, 3.0, y, z, kWall);
  }
  EXPECT_EQ(label_ramp_side_faces(points, {}), 0u);
  EXPECT_EQ(count(points, kWall), walls);
}

TEST(RampSideFaces, ASteepDeckIsNoDeck) {
  PointBuffer points = labelled();
  add_deck(points, 50.0);  // a wall band the network took for ramp
  add_side(points);
  PointBuffer loose_copy = points;
  EXPECT_EQ(label_ramp_side_faces(points, {}), 0u);
  RampSideSettings loose;
  loose.deck_max_slope_deg = 60.0;
  EXPECT_GT(label_ramp_side_faces(loose_copy, loose), 0u);  // the limit is what stopped it
}

TEST(RampSideFaces, ARidgeIsNoDeck) {
  // A gable the network took for ramp: two 45-degree roof faces meeting in
  // a ridge 0.5 m up. Cells on the ridge fit a gentle plane through both
  // faces, but a bent one; under the ridge's end stands a wall.
  PointBuffer points = labelled();
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 0.003);
  for (double x = 0.1; x <= 0.9; x += 0.01) {
    for (double y = 0.0; y <= 0.6; y += 0.02) add(points, x, y, 0.5 - std::abs(x - 0.5) + noise(rng), kInclined);
  }
  for (double x = 0.4; x <= 0.6; x += 0.02) {
    for (double z = 0.0; z <= 0.35; z += 0.02) add(points, x, -0.005, z, kWall);
  }
  PointBuffer loose_copy = points;
  EXPECT_EQ(label_ramp_side_faces(points, {}), 0u);
  RampSideSettings loose;
  loose.deck_max_curvature = 1.0;
  EXPECT_GT(label_ramp_side_faces(loose_copy, loose), 0u);  // the curvature limit is what stopped it
}

TEST(RampSideFaces, DecksAreRememberedAcrossScansUntilCleared) {
  PointBuffer first = labelled();
  add_deck(first);
  PointBuffer second = labelled();  // a camera low beside the ramp: the side alone
  const std::size_t side = add_side(second);
  PointBuffer alone = second;
  EXPECT_EQ(label_ramp_side_faces(alone, {}), 0u);

  RampDeckMemory memory({});
  EXPECT_EQ(memory.label_side_faces(first), 0u);
  EXPECT_GT(memory.columns(), 0u);
  PointBuffer again = second;
  EXPECT_EQ(memory.label_side_faces(again), side);
  memory.clear();
  EXPECT_EQ(memory.columns(), 0u);
  EXPECT_EQ(memory.label_side_faces(second), 0u);
}

TEST(RampSideFaces, DisabledOrUnlabelledChangesNothing) {
  PointBuffer points = labelled();
  add_deck(points);
  add_side(points);
  RampSideSettings off;
  off.enabled = false;
  EXPECT_EQ(label_ramp_side_faces(points, off), 0u);
  PointBuffer bare;
  bare.push_back(0.0f, 0.0f, 0.0f);
  EXPECT_EQ(label_ramp_side_faces(bare, {}), 0u);
  PointBuffer empty = labelled();
  EXPECT_EQ(label_ramp_side_faces(empty, {}), 0u);
}

TEST(RampSideFaces, RefusesBadSettingsAndNonFinitePoints) {
  const auto refused = [](auto change) {
    RampSideSettings s;
    change(s);
    EXPECT_THROW(RampDeckMemory{s}, Error);
  };
  refused([](RampSideSettings& s) { s.radius = 0.0; });
  refused([](RampSideSettings& s) { s.radius = std::numeric_limits<double>::quiet_NaN(); });
  refused([](RampSideSettings& s) { s.normal_cell = 0.001; });
  refused([](RampSideSettings& s) { s.min_rise = 0.5, s.max_rise = 0.2; });
  refused([](RampSideSettings& s) { s.min_rise = -0.1; });
  refused([](RampSideSettings& s) { s.max_rise = std::numeric_limits<double>::infinity(); });
  refused([](RampSideSettings& s) { s.deck_max_slope_deg = 0.0; });
  refused([](RampSideSettings& s) { s.deck_max_slope_deg = 91.0; });
  refused([](RampSideSettings& s) { s.deck_max_curvature = -0.01; });

  PointBuffer points = labelled();
  add(points, 0.0, 0.0, 0.0, kWall);  // no deck at all: refused all the same
  add(points, 0.1, std::numeric_limits<double>::quiet_NaN(), 0.0, kWall);
  try {
    label_ramp_side_faces(points, {});
    FAIL() << "a NaN point was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 1 is not finite"), std::string::npos) << e.what();
  }
}

TEST(RampSideFaces, PointsBeyondTheGridAreLeftAlone) {
  PointBuffer points = labelled();
  add_deck(points);
  add(points, 5.0e6, 0.0, 0.0, kWall);
  add(points, 5.0e6, 0.0, 0.5, kInclined);
  EXPECT_EQ(label_ramp_side_faces(points, {}), 0u);
  EXPECT_EQ(points.labels()[points.size() - 2], kWall);
}

}  // namespace
}  // namespace sarmap
