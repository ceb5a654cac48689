// The occupancy model's fixed point: OctoMap's defaults in 1/32 nat, settings
// whose values would not fit the map's one byte per voxel refused by name,
// and every value an update can produce stored exactly.
#include "engine/metric/occupancy_model.hpp"

#include <gtest/gtest.h>

#include <string>

#include "engine/core/error.hpp"

namespace sarmap::metric {
namespace {

std::string settings_error(const OccupancySettings& s) {
  try {
    OccupancyModel model(s);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(OccupancyModel, OctoMapDefaultsInThirtySecondsOfANat) {
  const OccupancyModel model;
  EXPECT_EQ(model.hit(), 27);    // log(0.7 / 0.3) = 0.847
  EXPECT_EQ(model.miss(), -13);  // log(0.4 / 0.6) = -0.405
  EXPECT_EQ(model.min(), -64);   // clamp 0.12: -1.992
  EXPECT_EQ(model.max(), 111);   // clamp 0.97: 3.476
  EXPECT_EQ(model.threshold(), 0);
  EXPECT_NEAR(OccupancyModel::probability(model.hit()), 0.7, 2e-3);
  EXPECT_NEAR(OccupancyModel::probability(model.miss()), 0.4, 2e-3);
  // An unknown voxel starts at 0; updates clamp as OctoMap's do.
  EXPECT_EQ(model.add(kUnknownLogOdds, model.hit()), 27);
  EXPECT_EQ(model.add(100, model.hit()), 111);
  EXPECT_EQ(model.add(-60, model.miss()), -64);
}

TEST(OccupancyModel, RefusesSettingsAByteCannotHold) {
  OccupancySettings s;
  s.clamp_max = 0.99;
  EXPECT_NE(settings_error(s).find("clamp_max must be at most 0.981"), std::string::npos) << settings_error(s);
  s = {};
  s.clamp_min = 0.01;
  EXPECT_NE(settings_error(s).find("clamp_min must be at least 0.018"), std::string::npos) << settings_error(s);
  s = {};
  s.prob_hit = 0.502;
  EXPECT_NE(settings_error(s).find("prob_hit must be at least 0.504"), std::string::npos) << settings_error(s);
  s = {};
  s.prob_miss = 0.499;
  EXPECT_NE(settings_error(s).find("prob_miss must be at most 0.496"), std::string::npos) << settings_error(s);
  // The widest clamps that fit are accepted.
  s = {};
  s.clamp_max = 0.981;
  s.clamp_min = 0.019;
  EXPECT_EQ(settings_error(s), "");
  EXPECT_LE(OccupancyModel(s).max(), kMaxStoredLogOdds);
  EXPECT_GE(OccupancyModel(s).min(), -kMaxStoredLogOdds);
}

TEST(OccupancyModel, EveryValueAnUpdateCanReachIsStoredExactly) {
  for (const double clamp_max : {0.97, 0.981}) {
    OccupancySettings s;
    s.clamp_max = clamp_max;
    s.clamp_min = 0.019;
    const OccupancyModel model(s);
    for (int v = model.min(); v <= model.max(); ++v) {
      const auto value = static_cast<std::int16_t>(v);
      ASSERT_TRUE(storable_log_odds(value)) << v;
      ASSERT_EQ(log_odds_of(stored_log_odds(value)), value) << v;
      ASSERT_NE(stored_log_odds(value), kStoredUnknownLogOdds) << v;
    }
  }
  EXPECT_EQ(log_odds_of(stored_log_odds(kUnknownLogOdds)), kUnknownLogOdds);
  EXPECT_FALSE(storable_log_odds(128));
  EXPECT_FALSE(storable_log_odds(-128));
  EXPECT_TRUE(storable_log_odds(-127));
}

}  // namespace
}  // namespace sarmap::metric
