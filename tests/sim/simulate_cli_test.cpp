// Tests of `sarmap simulate`: it writes a sequence the readers accept, with
// the same points the library simulates, and reports bad arenas clearly; a
// random arena is seen by the sensor its options ask for.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "engine/io/scan_source.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/random_arena.hpp"
#include "engine/sim/simulator.hpp"
#include "tests/sim/run_cli.hpp"
#include "tests/sim/test_arenas.hpp"

namespace sarmap::sim {
namespace {

class SimulateCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = sarmap::testing::scratch_dir(std::string("simulate_cli_") +
                                ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(SimulateCli, WritesAReadableSequence) {
  nlohmann::json j = testing::base_arena_json();
  j["elements"] = nlohmann::json::parse(R"([{"type": "wall", "from": [3.5, 0], "to": [3.5, 4], "height": 1.2,
                                              "thickness": 0.1}])");
  j["trajectory"]["frames"] = 4;
  j["sensor"]["noise"] = "kinect";
  std::ofstream(dir_ / "arena.json") << j.dump();
  const auto r = sarmap::testing::run_cli("simulate " + (dir_ / "arena.json").string() + " --out " + (dir_ / "seq").string() +
                                      " --seed 5 --frames 3",
                                  dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("test: 3 frames, "), std::string::npos) << r.out;  // no line per frame off a terminal
  auto source = open_scan_sequence(dir_ / "seq");
  ASSERT_EQ(source->size(), 3u);
  EXPECT_EQ(source->layout(), "sarmap");
  EXPECT_EQ(source->sensor().type, SensorType::DepthCamera);
  EXPECT_DOUBLE_EQ(source->sensor().max_range, 6.0);
  const Simulator sim(testing::parse_test_arena(j), {.seed = 5});
  Scan scan;
  for (std::size_t f = 0; f < 3; ++f) {
    ASSERT_TRUE(source->next(scan));
    const Scan expected = sim.simulate(f);
    ASSERT_EQ(scan.points.size(), expected.points.size());
    ASSERT_TRUE(scan.points.has_labels());
    EXPECT_TRUE(scan.origin.isApprox(expected.origin, 1e-9));
    EXPECT_TRUE(scan.pose.matrix().isApprox(expected.pose.matrix(), 1e-9));
    for (std::size_t i = 0; i < scan.points.size(); i += 7) {
      ASSERT_EQ(scan.points.x()[i], expected.points.x()[i]);
      ASSERT_EQ(scan.points.z()[i], expected.points.z()[i]);
      ASSERT_EQ(scan.points.labels()[i], expected.points.labels()[i]);
    }
  }
  EXPECT_FALSE(source->next(scan));
}

TEST_F(SimulateCli, RandomArenaIsSavedAndSimulated) {
  const auto r = sarmap::testing::run_cli("simulate --random 17 --write-arena " + (dir_ / "random.json").string() +
                                      " --out " + (dir_ / "seq").string() + " --frames 2 --quiet",
                                  dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  const Arena a = load_arena(dir_ / "random.json");
  EXPECT_EQ(a.name, "random-17");
  EXPECT_EQ(open_scan_sequence(dir_ / "seq")->size(), 2u);
}

// A shorter simulation into the folder of a longer one: the old frames go,
// files simulate did not write stay.
TEST_F(SimulateCli, ReplacesAnEarlierSequenceAndKeepsForeignFiles) {
  nlohmann::json j = testing::base_arena_json();
  j["trajectory"]["frames"] = 6;
  std::ofstream(dir_ / "arena.json") << j.dump();
  const std::string simulate = "simulate " + (dir_ / "arena.json").string() + " --out " + (dir_ / "seq").string();
  ASSERT_EQ(sarmap::testing::run_cli(simulate + " --quiet", dir_).exit_code, 0);
  ASSERT_TRUE(std::filesystem::exists(dir_ / "seq" / "frame_000005.ply"));
  std::ofstream(dir_ / "seq" / "notes.txt") << "the operator's notes";
  std::ofstream(dir_ / "seq" / "frame_000005.pcd") << "not simulate's name";

  const auto r = sarmap::testing::run_cli(simulate + " --frames 3 --quiet", dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(dir_ / "seq")) {
    left.push_back(entry.path().filename().string());
  }
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"frame_000000.ply", "frame_000001.ply", "frame_000002.ply",
                                            "frame_000005.pcd", "notes.txt", "sequence.json"}));
  EXPECT_EQ(sarmap::testing::slurp(dir_ / "seq" / "notes.txt"), "the operator's notes");
  EXPECT_EQ(open_scan_sequence(dir_ / "seq")->size(), 3u);
}

TEST_F(SimulateCli, BadArenaFailsWithItsMessage) {
  nlohmann::json j = testing::base_arena_json();
  j["elements"] = nlohmann::json::parse(R"([{"type": "inclined_ramp", "center": [2, 1], "length": 1.2,
                                              "width": 1.0, "angle_deg": 95}])");
  std::ofstream(dir_ / "bad.json") << j.dump();
  const auto r = sarmap::testing::run_cli("simulate " + (dir_ / "bad.json").string() + " --out " + (dir_ / "seq").string(), dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.json: elements[0] (inclined_ramp): angle_deg must be in (0, 90), got 95"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "seq" / "sequence.json"));
  const auto none = sarmap::testing::run_cli("simulate --out " + (dir_ / "seq").string(), dir_);
  EXPECT_NE(none.exit_code, 0);
  EXPECT_NE(none.err.find("give ARENA.json or --random SEED"), std::string::npos) << none.err;
  // A negative seed had wrapped round to 2^64 - 1 and been accepted.
  for (const char* option : {"--random -1", "--seed -1 --random 3"}) {
    const auto negative = sarmap::testing::run_cli(std::string("simulate ") + option + " --out " + (dir_ / "seq").string(), dir_);
    EXPECT_NE(negative.exit_code, 0) << option;
    EXPECT_NE(negative.err.find(std::string(option).substr(0, 6)), std::string::npos) << negative.err;
  }
}

TEST_F(SimulateCli, RandomArenaSeenByALidar) {
  const auto r = sarmap::testing::run_cli(
      "simulate --random 17 --sensor lidar --rings 16 --samples 360 --vertical-fov -20,10 --min-range 0.4 "
      "--max-range 6 --sensor-height 0.6 --write-arena " +
          (dir_ / "lidar.json").string() + " --out " + (dir_ / "seq").string() + " --frames 3 --quiet",
      dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Arena a = load_arena(dir_ / "lidar.json");
  EXPECT_EQ(a.sensor.type, SensorType::Lidar);
  EXPECT_EQ(a.sensor.rings, 16);
  EXPECT_EQ(a.sensor.horizontal_samples, 360);
  EXPECT_DOUBLE_EQ(a.sensor.vertical_fov_min_deg, -20);
  EXPECT_DOUBLE_EQ(a.sensor.vertical_fov_max_deg, 10);
  EXPECT_DOUBLE_EQ(a.trajectory.height, 0.6);
  auto source = open_scan_sequence(dir_ / "seq");
  ASSERT_EQ(source->size(), 3u);
  EXPECT_EQ(source->sensor().type, SensorType::Lidar);
  EXPECT_DOUBLE_EQ(source->sensor().min_range, 0.4);
  EXPECT_DOUBLE_EQ(source->sensor().max_range, 6.0);
  EXPECT_FALSE(source->sensor().intrinsics.has_value());
  Scan scan;
  while (source->next(scan)) {
    ASSERT_GT(scan.points.size(), 1000u);
    EXPECT_LE(scan.points.size(), 16u * 360u);
    // Within the range up to the range noise (Gaussian, sigma 1 cm).
    for (std::size_t i = 0; i < scan.points.size(); ++i) {
      const Eigen::Vector3d p(scan.points.x()[i], scan.points.y()[i], scan.points.z()[i]);
      const double range = (p - scan.origin).norm();
      ASSERT_GE(range, 0.4 - 0.06) << i;
      ASSERT_LE(range, 6.0 + 0.06) << i;
    }
  }
}

TEST_F(SimulateCli, RandomArenaSeenByAnotherDepthCamera) {
  const auto r = sarmap::testing::run_cli(
      "simulate --random 17 --sensor depth --width 160 --height 120 --pitch -20 "
      "--max-range 4 --out " +
          (dir_ / "seq").string() + " --frames 2 --quiet",
      dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto source = open_scan_sequence(dir_ / "seq");
  EXPECT_EQ(source->sensor().type, SensorType::DepthCamera);
  EXPECT_DOUBLE_EQ(source->sensor().min_range, 0.3);
  EXPECT_DOUBLE_EQ(source->sensor().max_range, 4.0);
  ASSERT_TRUE(source->sensor().intrinsics.has_value());
  EXPECT_EQ(source->sensor().intrinsics->width, 160);
  EXPECT_EQ(source->sensor().intrinsics->height, 120);
  EXPECT_DOUBLE_EQ(source->sensor().intrinsics->fx, 138.5);
  Scan scan;
  while (source->next(scan)) EXPECT_LE(scan.points.size(), 160u * 120u);
}

// No sensor option: the sequence is byte for byte the one of today's arena
// text (pinned in random_arena_test), simulated from a file.
TEST_F(SimulateCli, RandomArenaDefaultSensorIsUnchanged) {
  const Arena pinned = random_arena(17);
  ASSERT_EQ(pinned.sha256, "74cf334adf237aed554876650bf537076cc63b3a284467be186cb260bd8d0727");
  std::ofstream(dir_ / "random-17.json", std::ios::binary) << random_arena_json(17);
  ASSERT_EQ(sarmap::testing::run_cli(
                "simulate --random 17 --out " + (dir_ / "a").string() + " --frames 2 --quiet", dir_)
                .exit_code,
            0);
  ASSERT_EQ(sarmap::testing::run_cli("simulate " + (dir_ / "random-17.json").string() + " --out " +
                                         (dir_ / "b").string() + " --frames 2 --quiet",
                                     dir_)
                .exit_code,
            0);
  for (const char* file : {"sequence.json", "frame_000000.ply", "frame_000001.ply"}) {
    EXPECT_EQ(sarmap::testing::slurp(dir_ / "a" / file), sarmap::testing::slurp(dir_ / "b" / file)) << file;
  }
}

TEST_F(SimulateCli, BadSensorOptionsAreUsageErrors) {
  const std::string out = " --out " + (dir_ / "seq").string() + " --frames 1 --quiet";
  const std::pair<std::string, std::string> cases[] = {
      {"--random 3 --sensor lidar --rings 0", "--rings"},
      {"--random 3 --sensor lidar --max-range -2", "--max-range"},
      {"--random 3 --sensor lidar --min-range -1", "--min-range"},
      {"--random 3 --sensor lidar --min-range 8 --max-range 4", "--max-range"},
      {"--random 3 --sensor lidar --vertical-fov=-95,10", "--vertical-fov"},
      {"--random 3 --sensor lidar --vertical-fov 10,-10", "--vertical-fov"},
      {"--random 3 --sensor lidar --samples 0", "--samples"},
      {"--random 3 --sensor lidar --width 640", "--width"},
      {"--random 3 --rings 16", "--rings"},
      {"--random 3 --sensor sonar", "--sensor"},
      {"--random 3 --sensor-height 0", "--sensor-height"},
      {"--random 3 --pitch 95", "--pitch"},
      {"--random 3 --width 0", "--width"},
      {"datasets/arenas/esogu-6x4.json --sensor lidar", "needs --random"},
  };
  for (const auto& [options, named] : cases) {
    const auto r = sarmap::testing::run_cli("simulate " + options + out, dir_);
    EXPECT_EQ(r.exit_code, 2) << options << ": " << r.err;
    EXPECT_NE(r.err.find("sarmap: error: "), std::string::npos) << options << ": " << r.err;
    EXPECT_NE(r.err.find(named), std::string::npos) << options << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "seq" / "sequence.json"));
}

}  // namespace
}  // namespace sarmap::sim
