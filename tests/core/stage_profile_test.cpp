#include "engine/core/stage_profile.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "engine/core/state_stream.hpp"

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

// A scan's latency is its stage times' sum unless set (stages of two scans
// overlapping); appended rows keep theirs, and counters add up by stage name.
TEST(StageProfile, LatencyPerScanAndAppendedRows) {
  StageProfile profile;
  profile.begin_scan();
  profile.add_time("read", 0.002);
  profile.add_time("metric", 0.003);
  profile.add_count("metric", "rays", 10);

  StageProfile in_flight;  // stages first seen in another order, one new
  in_flight.begin_scan();
  in_flight.add_time("metric", 0.004);
  in_flight.add_time("classify", 0.010);
  in_flight.add_count("metric", "rays", 5);
  in_flight.add_count("classify", "blocks", 2);
  in_flight.set_latency(0.030);
  profile.append(in_flight);

  ASSERT_EQ(profile.scan_count(), 2u);
  EXPECT_EQ(profile.stage_names(), (std::vector<std::string>{"read", "metric", "classify"}));
  EXPECT_DOUBLE_EQ(profile.stats("metric").total_s, 0.007);
  EXPECT_DOUBLE_EQ(profile.stats("classify").max_s, 0.010);
  EXPECT_DOUBLE_EQ(profile.counter("metric", "rays"), 15);
  EXPECT_DOUBLE_EQ(profile.counter("classify", "blocks"), 2);
  const StageProfile::StageStats latency = profile.latency();
  EXPECT_EQ(latency.scans, 2u);
  EXPECT_DOUBLE_EQ(latency.p50_s, 0.005);
  EXPECT_DOUBLE_EQ(latency.max_s, 0.030);
  const auto j = nlohmann::json::parse(profile.json());
  EXPECT_DOUBLE_EQ(j["latency"]["max_s"].get<double>(), 0.030);
  EXPECT_DOUBLE_EQ(j["per_scan"][1]["latency_s"].get<double>(), 0.030);
  EXPECT_NE(profile.table().find("latency"), std::string::npos);

  // A skipped scan's row goes with its latency; the state keeps the rest.
  profile.begin_scan();
  profile.set_latency(1.0);
  profile.skip_scan(7, "frame 7", "damaged", /*row_open=*/true);
  EXPECT_DOUBLE_EQ(profile.latency().max_s, 0.030);
  StateWriter out;
  profile.save_state(out);
  StageProfile loaded;
  const std::string bytes = out.bytes();
  StateReader in(bytes, "profile");
  loaded.load_state(in);
  EXPECT_EQ(loaded.json(), profile.json());
}

// Levels travel with their rows: a scan timed apart keeps its map bytes.
TEST(StageProfile, AppendedRowsKeepTheirLevels) {
  StageProfile profile;
  profile.begin_scan();
  profile.add_time("metric", 0.001);
  profile.set_level("metric", "map_bytes", 10.0);
  StageProfile in_flight;
  in_flight.begin_scan();
  in_flight.set_level("classify", "point_map_bytes", 3.0);  // a level new to `profile`
  in_flight.set_level("metric", "map_bytes", 20.0);
  in_flight.begin_scan();
  in_flight.add_time("metric", 0.001);  // sets none
  profile.append(in_flight);
  ASSERT_EQ(profile.scan_count(), 3u);
  EXPECT_EQ(profile.level("metric", "map_bytes").scans, 2u);
  EXPECT_DOUBLE_EQ(profile.level("metric", "map_bytes").last, 20.0);
  EXPECT_EQ(profile.level("classify", "point_map_bytes").scans, 1u);
  const auto j = nlohmann::json::parse(profile.json());
  EXPECT_FALSE(j["per_scan"][0].contains("classify_point_map_bytes"));
  EXPECT_DOUBLE_EQ(j["per_scan"][1]["classify_point_map_bytes"].get<double>(), 3.0);
  EXPECT_FALSE(j["per_scan"][2].contains("metric_map_bytes"));
}

TEST(StageProfile, LevelsAreKeptPerScanNotSummed) {
  StageProfile profile;
  for (double bytes : {100.0, 300.0, 200.0}) {
    profile.begin_scan();
    profile.add_time("metric", 0.01);
    profile.set_level("metric", "map_bytes", bytes);
  }
  profile.begin_scan();
  profile.add_time("metric", 0.01);  // a scan that sets no level
  const auto level = profile.level("metric", "map_bytes");
  EXPECT_EQ(level.scans, 3u);
  EXPECT_DOUBLE_EQ(level.last, 200.0);
  EXPECT_DOUBLE_EQ(level.max, 300.0);
  EXPECT_EQ(profile.level("metric", "other").scans, 0u);
  const auto j = nlohmann::json::parse(profile.json());
  EXPECT_DOUBLE_EQ(j["stages"]["metric"]["map_bytes"].get<double>(), 200.0);
  EXPECT_DOUBLE_EQ(j["stages"]["metric"]["map_bytes_max"].get<double>(), 300.0);
  ASSERT_EQ(j["per_scan"].size(), 4u);
  EXPECT_DOUBLE_EQ(j["per_scan"][1]["metric_map_bytes"].get<double>(), 300.0);
  EXPECT_FALSE(j["per_scan"][3].contains("metric_map_bytes"));
  // A level first set in a later scan is absent from the rows before it.
  profile.set_level("classify", "point_map_bytes", 7.0);
  const auto k = nlohmann::json::parse(profile.json());
  EXPECT_FALSE(k["per_scan"][0].contains("classify_point_map_bytes"));
  EXPECT_DOUBLE_EQ(k["per_scan"][3]["classify_point_map_bytes"].get<double>(), 7.0);
}

// Rows are stored one after another in one array: a stage or level first
// seen late widens every row before it without moving their values.
TEST(StageProfile, StagesAndLevelsFirstSeenLateLeaveEarlierRowsAsTheyWere) {
  StageProfile profile;
  for (int scan = 0; scan < 5; ++scan) {
    profile.begin_scan();
    profile.add_time("read", 0.001 * (scan + 1));
    if (scan >= 2) profile.add_time("metric", 0.01 * (scan + 1));
    if (scan >= 3) profile.set_level("segment", "bytes", 1000.0 * scan);
    profile.add_time("topo", 0.1 * (scan + 1));
    if (scan >= 1) profile.set_level("metric", "map_bytes", 10.0 * scan);
  }
  const auto j = nlohmann::json::parse(profile.json());
  ASSERT_EQ(j["per_scan"].size(), 5u);
  for (int scan = 0; scan < 5; ++scan) {
    const auto& row = j["per_scan"][scan];
    EXPECT_DOUBLE_EQ(row["read_s"].get<double>(), 0.001 * (scan + 1)) << scan;
    EXPECT_DOUBLE_EQ(row["metric_s"].get<double>(), scan >= 2 ? 0.01 * (scan + 1) : 0.0) << scan;
    EXPECT_DOUBLE_EQ(row["topo_s"].get<double>(), 0.1 * (scan + 1)) << scan;
    EXPECT_EQ(row.contains("metric_map_bytes"), scan >= 1) << scan;
    EXPECT_EQ(row.contains("segment_bytes"), scan >= 3) << scan;
    if (scan >= 1) {
      EXPECT_DOUBLE_EQ(row["metric_map_bytes"].get<double>(), 10.0 * scan) << scan;
    }
    if (scan >= 3) {
      EXPECT_DOUBLE_EQ(row["segment_bytes"].get<double>(), 1000.0 * scan) << scan;
    }
  }
  EXPECT_DOUBLE_EQ(profile.stats("topo").total_s, 1.5);
  EXPECT_NEAR(profile.latency().max_s, 0.005 + 0.05 + 0.5, 1e-12);
  profile.skip_scan(4, "frame 4", "refused", true);
  EXPECT_EQ(profile.scan_count(), 4u);
  EXPECT_DOUBLE_EQ(profile.level("segment", "bytes").last, 3000.0);
  EXPECT_NEAR(profile.stats("read").total_s, 0.010, 1e-12);
}

TEST(StageProfile, ASkippedScanTakesItsLevelsWithIt) {
  StageProfile profile;
  profile.begin_scan();
  profile.set_level("metric", "map_bytes", 10.0);
  profile.begin_scan();
  profile.set_level("metric", "map_bytes", 50.0);
  profile.skip_scan(1, "frame 1", "refused", true);
  const auto level = profile.level("metric", "map_bytes");
  EXPECT_EQ(level.scans, 1u);
  EXPECT_DOUBLE_EQ(level.max, 10.0);
}

TEST(StageProfile, LevelsSurviveACheckpoint) {
  StageProfile profile;
  for (int scan = 0; scan < 3; ++scan) {
    profile.begin_scan();
    profile.add_time("metric", 0.01);
    profile.set_level("metric", "map_bytes", 100.0 * scan);
    if (scan == 1) profile.set_level("classify", "point_map_bytes", 5.0);
  }
  StateWriter out;
  profile.save_state(out);
  StageProfile back;
  StateReader in(out.bytes(), "state.bin");
  back.load_state(in);
  EXPECT_EQ(back.json(), profile.json());
  // And it goes on from there.
  back.begin_scan();
  back.set_level("metric", "map_bytes", 50.0);
  EXPECT_DOUBLE_EQ(back.level("metric", "map_bytes").max, 200.0);
  EXPECT_EQ(back.level("metric", "map_bytes").scans, 4u);
}

}  // namespace
}  // namespace sarmap
