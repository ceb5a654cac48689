#include "engine/core/stage_profile.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace sarmap {
namespace {

TEST(StageProfile, StatisticsPerStage) {
  StageProfile profile;
  for (int scan = 1; scan <= 20; ++scan) {
    profile.begin_scan();
    profile.add_time("read", 0.001 * scan);
    profile.add_time("metric", 0.01);
    profile.add_count("metric", "rays", 100);
  }
  const auto read = profile.stats("read");
  EXPECT_EQ(read.scans, 20u);
  EXPECT_NEAR(read.total_s, 0.21, 1e-12);
  EXPECT_NEAR(read.mean_s, 0.0105, 1e-12);
  EXPECT_NEAR(read.p50_s, 0.010, 1e-12);
  EXPECT_NEAR(read.p95_s, 0.019, 1e-12);
  EXPECT_NEAR(read.max_s, 0.020, 1e-12);
  EXPECT_DOUBLE_EQ(profile.counter("metric", "rays"), 2000);
  EXPECT_EQ(profile.stage_names().size(), 2u);
}

TEST(StageProfile, JsonFollowsTheProfileFormat) {
  StageProfile profile;
  profile.begin_scan();
  { auto timer = profile.time("read"); }
  profile.add_count("read", "points_in", 42);
  profile.begin_scan();
  profile.add_time("preprocess", 0.5);
  profile.set_wall_seconds(2.0);
  const auto j = nlohmann::json::parse(profile.json());
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["units"], "s");
  EXPECT_EQ(j["scans"], 2);
  EXPECT_DOUBLE_EQ(j["scans_per_second"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["stages"]["read"]["points_in"].get<double>(), 42);
  EXPECT_DOUBLE_EQ(j["stages"]["preprocess"]["total_s"].get<double>(), 0.5);
  ASSERT_EQ(j["per_scan"].size(), 2u);
  // A stage first seen in scan 2 reads 0 in scan 1.
  EXPECT_DOUBLE_EQ(j["per_scan"][0]["preprocess_s"].get<double>(), 0.0);
  EXPECT_GE(j["per_scan"][0]["read_s"].get<double>(), 0.0);
  EXPECT_NE(profile.table().find("preprocess"), std::string::npos);
}

}  // namespace
}  // namespace sarmap
