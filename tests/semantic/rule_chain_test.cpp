// The chain of label-correcting rules (engine/semantic/rules/rule_chain.hpp)
// against its plain reference, the four rule functions called one after
// another in the documented order: on a hand-made scene where each rule has
// something to change, on random labelled clouds, with each rule disabled
// by name, and on edge cases (empty, unlabelled, non-finite). Also: reapply
// remembers no decks, the decks survive a save and load, names are checked.
#include "engine/semantic/rules/rule_chain.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/core/state_stream.hpp"
#include "tests/semantic/labelled_points.hpp"

namespace sarmap {
namespace {

using testing::add;
using testing::kInclined;
using testing::kOther;
using testing::kTerrain;
using testing::kWall;

// A wedge ramp's deck (20 degrees, x in [0, 1]) labelled inclined ramp and
// its side face under the edge y = 0 labelled wall: ramp_sides' case.
void add_ramp_with_wall_side(PointBuffer& points) {
  const double rise = std::tan(20.0 * std::numbers::pi / 180.0);
  for (double x = 0.0; x <= 1.0; x += 0.02) {
    for (double y = 0.0; y <= 0.6; y += 0.02) add(points, x, y, x * rise, kInclined);
  }
  for (double x = 0.1; x <= 1.0; x += 0.02) {
    for (double z = 0.0; z <= x * rise - 0.03; z += 0.02) add(points, x, -0.005, z, kWall);
  }
}

// A 3 m band labelled other: wall_bands' case.
void add_band_of_other(PointBuffer& points) {
  for (double t = 0.0; t <= 3.0; t += 0.02) {
    for (double z = 0.0; z <= 0.4; z += 0.04) add(points, 4.0 + t, 3.005, z, kOther);
  }
}

// A vertical wall labelled inclined ramp: ramp_veto's case.
void add_wall_called_ramp(PointBuffer& points) {
  for (double y = 0.0; y <= 1.0; y += 0.02) {
    for (double z = 0.0; z <= 1.0; z += 0.02) add(points, 8.005, 6.0 + y, z, kInclined);
  }
}

// A floor with its strip before a wall labelled wall at floor height: wall_feet's case.
void add_floor_with_wall_feet(PointBuffer& points) {
  int i = 0;
  for (double x = 0.0; x < 0.999; x += 0.02) {
    for (double y = 0.0; y < 0.999; y += 0.02, ++i) add(points, 10.0 + x, y, i % 2 == 0 ? 0.003 : -0.003, kTerrain);
  }
  for (double y = 0.0; y < 0.999; y += 0.02) {
    for (double z = 0.02; z <= 0.5; z += 0.02) add(points, 11.0, y, z, kWall);
    for (double x = 0.965; x < 0.999; x += 0.01) add(points, 10.0 + x, y, 0.001, kWall);
  }
}

PointBuffer scene() {
  PointBuffer points = testing::labelled();
  add_ramp_with_wall_side(points);
  add_band_of_other(points);
  add_wall_called_ramp(points);
  add_floor_with_wall_feet(points);
  return points;
}

// Random points in a 4 x 4 x 1 m box, clustered on a few planes so that
// the rules' neighbourhoods fill, with random labels and score channels.
PointBuffer random_cloud(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 4.0), h(0.0, 1.0);
  std::uniform_int_distribution<int> label(0, 5), plane(0, 3);
  PointBuffer points = testing::labelled();
  std::vector<std::size_t> channels;
  for (const char* name : {"terrain", "wall", "inclined_ramp", "flat_ramp", "other"}) channels.push_back(points.add_score(name));
  for (int i = 0; i < 6000; ++i) {
    const double a = u(rng), b = u(rng), c = h(rng);
    switch (plane(rng)) {
      case 0: add(points, a, b, 0.0, static_cast<std::uint8_t>(label(rng))); break;         // floor
      case 1: add(points, 2.0, a, c, static_cast<std::uint8_t>(label(rng))); break;         // wall
      case 2: add(points, a, b, 0.3 * a, static_cast<std::uint8_t>(label(rng))); break;     // slope
      default: add(points, a, b, c, static_cast<std::uint8_t>(label(rng))); break;          // clutter
    }
    for (std::size_t ch : channels) points.score(ch).back() = static_cast<float>(h(rng));
  }
  return points;
}

// The plain reference: each rule's own function, in the chain's order.
RuleChanges reference(PointBuffer& points, const RuleChainSettings& s) {
  RuleChanges changes;
  changes.changed[0] = veto_steep_inclined_ramps(points, s.ramp_veto);
  changes.changed[1] = label_wall_bands(points, s.wall_bands);
  changes.changed[2] = label_ramp_side_faces(points, s.ramp_sides);
  changes.changed[3] = label_wall_feet(points, s.wall_feet);
  return changes;
}

void expect_same_points(const PointBuffer& a, const PointBuffer& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t p = 0; p < a.size(); ++p) ASSERT_EQ(a.labels()[p], b.labels()[p]) << p;
  ASSERT_EQ(a.score_count(), b.score_count());
  for (std::size_t c = 0; c < a.score_count(); ++c) {
    for (std::size_t p = 0; p < a.size(); ++p) ASSERT_EQ(a.score(c)[p], b.score(c)[p]) << c << " " << p;
  }
}

TEST(RuleChain, AppliesEachRuleInOrderAsItsOwnFunctionDoes) {
  PointBuffer by_chain = scene(), by_reference = scene();
  RuleChain chain({});
  const RuleChanges changes = chain.apply(by_chain);
  const RuleChanges expected = reference(by_reference, {});
  expect_same_points(by_chain, by_reference);
  for (std::size_t r = 0; r < kRuleCount; ++r) {
    EXPECT_EQ(changes.changed[r], expected.changed[r]) << kRuleNames[r];
    EXPECT_GT(changes.changed[r], 50u) << kRuleNames[r] << ": the scene gives every rule work";
  }
  EXPECT_EQ(changes.of("ramp_sides"), changes.changed[2]);
  EXPECT_EQ(changes.total(), changes.changed[0] + changes.changed[1] + changes.changed[2] + changes.changed[3]);
}

TEST(RuleChain, AgreesWithTheReferenceOnRandomClouds) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    PointBuffer by_chain = random_cloud(seed), by_reference = random_cloud(seed);
    RuleChain chain({});
    const RuleChanges changes = chain.apply(by_chain);
    const RuleChanges expected = reference(by_reference, {});
    expect_same_points(by_chain, by_reference);
    EXPECT_EQ(changes.changed, expected.changed) << seed;
    EXPECT_GT(changes.total(), 0u) << seed;
  }
}

TEST(RuleChain, ADisabledRuleChangesNothingAndTheOthersStillRun) {
  for (std::string_view off : kRuleNames) {
    RuleChainSettings s;
    rule_enabled(s, off) = false;
    EXPECT_FALSE(rule_enabled(static_cast<const RuleChainSettings&>(s), off));
    PointBuffer by_chain = scene(), by_reference = scene();
    RuleChain chain(s);
    const RuleChanges changes = chain.apply(by_chain);
    EXPECT_EQ(changes.of(off), 0u) << off;
    EXPECT_EQ(changes.changed, reference(by_reference, s).changed) << off;
    expect_same_points(by_chain, by_reference);
  }
  RuleChainSettings none;
  for (std::string_view rule : kRuleNames) rule_enabled(none, rule) = false;
  PointBuffer points = scene();
  const PointBuffer before = points;
  EXPECT_EQ(RuleChain(none).apply(points).total(), 0u);
  expect_same_points(points, before);
}

// Ramp decks are remembered by apply(), not by reapply(): a side face seen
// without its deck becomes ramp only under a deck an applied scan showed.
TEST(RuleChain, ReapplyUsesTheDecksSeenAndRemembersNoneOfItsOwn) {
  PointBuffer ramp = testing::labelled();
  add_ramp_with_wall_side(ramp);
  PointBuffer side_only = testing::labelled();
  for (std::size_t p = 0; p < ramp.size(); ++p) {
    if (ramp.labels()[p] == kWall) add(side_only, ramp.x()[p], ramp.y()[p], ramp.z()[p], kWall);
  }
  ASSERT_GT(side_only.size(), 100u);

  RuleChain reapplied({});
  PointBuffer copy = ramp;
  reapplied.reapply(copy);  // sees the deck, must not remember it
  PointBuffer side = side_only;
  EXPECT_EQ(reapplied.reapply(side).of("ramp_sides"), 0u);
  EXPECT_EQ(reapplied.apply(side).of("ramp_sides"), 0u);

  RuleChain applied({});
  copy = ramp;
  applied.apply(copy);
  side = side_only;
  EXPECT_EQ(applied.reapply(side).of("ramp_sides"), side_only.size());
}

TEST(RuleChain, RememberedDecksSurviveASaveAndLoad) {
  RuleChain chain({});
  PointBuffer ramp = testing::labelled();
  add_ramp_with_wall_side(ramp);
  chain.apply(ramp);
  StateWriter out;
  chain.save_state(out);
  RuleChain loaded({});
  StateReader in(out.bytes(), "rule chain state");
  loaded.load_state(in);
  PointBuffer a = testing::labelled(), b = testing::labelled();
  add(a, 0.5, -0.005, 0.05, kWall), add(b, 0.5, -0.005, 0.05, kWall);
  EXPECT_EQ(chain.reapply(a).of("ramp_sides"), 1u);
  EXPECT_EQ(loaded.reapply(b).of("ramp_sides"), 1u);
}

TEST(RuleChain, EdgeCasesAndBadInput) {
  RuleChain chain({});
  PointBuffer empty = testing::labelled();
  EXPECT_EQ(chain.apply(empty).total(), 0u);
  PointBuffer unlabelled;
  unlabelled.push_back(0.0f, 0.0f, 0.0f);
  EXPECT_EQ(chain.apply(unlabelled).total(), 0u);
  EXPECT_FALSE(unlabelled.has_labels());

  PointBuffer nan = scene();
  nan.x()[5] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(chain.apply(nan), Error);

  RuleChainSettings s;
  EXPECT_THROW(rule_enabled(s, "wall_legs"), Error);
  try {
    rule_enabled(s, "wall_legs");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("wall_legs"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(rule_name_list()), std::string::npos) << e.what();
  }
  EXPECT_THROW(RuleChanges{}.of("ramp"), Error);
  EXPECT_EQ(rule_name_list(), "ramp_veto, wall_bands, ramp_sides, wall_feet");

  // Bad settings are refused even for a rule that is off: the config is wrong either way.
  s.wall_bands.enabled = false;
  s.wall_bands.column = 0.0;
  EXPECT_THROW(RuleChain{s}, Error);
  s = {};
  s.ramp_veto.enabled = false;
  s.ramp_veto.min_slope_deg = 120.0;
  EXPECT_THROW(RuleChain{s}, Error);
  s = {};
  s.ramp_sides.min_rise = 2.0;
  EXPECT_THROW(RuleChain{s}, Error);
  s = {};
  s.wall_feet.min_floor_points = 0;
  EXPECT_THROW(RuleChain{s}, Error);
}

}  // namespace
}  // namespace sarmap
