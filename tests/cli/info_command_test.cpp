// `sarmap info` on clouds and sequences, text and --json, and its errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <array>
#include <nlohmann/json.hpp>
#include <string>

#include "engine/io/point_cloud_file.hpp"
#include "engine/io/sequence_writer.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/cli/frame_sequence.hpp"
#include "tests/io/png_test_writer.hpp"
#include "tests/io/scratch_folder.hpp"

namespace sarmap {
namespace {

using test::quoted;
using test::run_cli;
using ::testing::HasSubstr;

const std::string kData = SARMAP_TEST_DATA_DIR;

TEST(CliBasics, VersionAndHelpOnEverySubcommandExitZero) {
  test::ScratchFolder dir;
  const auto version = run_cli("--version", dir.path());
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_THAT(version.out, HasSubstr("sarmap "));
  for (const std::string sub : {"", "info ", "convert "}) {
    const auto help = run_cli(sub + "--help", dir.path());
    EXPECT_EQ(help.exit_code, 0) << sub;
    EXPECT_THAT(help.out, HasSubstr("Usage")) << sub;
  }
  const auto unknown = run_cli("info --no-such-flag x", dir.path());
  EXPECT_NE(unknown.exit_code, 0);
}

TEST(CliInfo, CloudReportsPointsFieldsAndBounds) {
  test::ScratchFolder dir;
  PointBuffer points;
  for (int i = 0; i < 7; ++i) points.push_back(static_cast<float>(i), -1.0f, 0.5f * static_cast<float>(i));
  points.enable_labels();
  points.labels()[0] = 2;
  write_point_cloud(dir / "c.ply", points);
  const auto r = run_cli("info " + quoted((dir / "c.ply").string()), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("points: 7\n"));
  EXPECT_THAT(r.out, HasSubstr("fields: x y z label"));
  EXPECT_THAT(r.out, HasSubstr("min (0.000, -1.000, 0.000)  max (6.000, -1.000, 3.000)"));
  EXPECT_THAT(r.out, HasSubstr("terrain 0 wall 1"));
  EXPECT_EQ(r.err, "");

  const auto j = run_cli("info --json " + quoted((dir / "c.ply").string()), dir.path());
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto parsed = nlohmann::json::parse(j.out);
  EXPECT_EQ(parsed["kind"], "cloud");
  EXPECT_EQ(parsed["points"], 7);
  EXPECT_EQ(parsed["bounds"]["max"][2], 3.0);
  EXPECT_EQ(parsed["classes"]["unknown"], 6);
}

TEST(CliInfo, CommittedSequenceReportsFramesPointsAndPoseRange) {
  test::ScratchFolder dir;
  const auto r = run_cli("info " + quoted(kData + "/sequences/tiny"), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("layout: sarmap"));
  EXPECT_THAT(r.out, HasSubstr("frames: 2\n"));
  EXPECT_THAT(r.out, HasSubstr("sensor: lidar"));
  EXPECT_THAT(r.out, HasSubstr("points: 5\n"));
  // The second frame's points are turned about z and moved by (3, 4, 0).
  EXPECT_THAT(r.out, HasSubstr("max (3.000, 4.500, 2.000)"));
  EXPECT_THAT(r.out, HasSubstr("path length 5.000 m"));
  EXPECT_EQ(r.err, "");  // no progress line: stderr is not a terminal
}

TEST(CliInfo, SequenceJsonAgreesWithWhatWasWritten) {
  test::ScratchFolder dir;
  SensorInfo sensor;
  sensor.type = SensorType::Lidar;
  sensor.max_range = 12;
  SequenceWriter writer(dir / "seq", sensor);
  std::size_t total = 0;
  double path = 0;
  for (int f = 0; f < 4; ++f) {
    Scan scan;
    scan.pose = Pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(f * 3.0, f * 4.0, 1.0));
    if (f > 0) path += 5.0;
    scan.origin = scan.pose.translation();
    scan.timestamp = 0.25 * f;
    for (int p = 0; p <= f * 10; ++p)
      scan.points.push_back(static_cast<float>(p), 0.0f, static_cast<float>(f));
    total += scan.points.size();
    writer.add(scan);
  }
  writer.finish();
  const auto r = run_cli("info --json --quiet " + quoted((dir / "seq").string()), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["kind"], "sequence");
  EXPECT_EQ(j["layout"], "sarmap");
  EXPECT_EQ(j["frames"], 4);
  EXPECT_EQ(j["points"], total);
  EXPECT_EQ(j["sensor"]["type"], "lidar");
  EXPECT_EQ(j["sensor"]["max_range"], 12.0);
  EXPECT_DOUBLE_EQ(j["poses"]["path_length"].get<double>(), path);
  EXPECT_EQ(j["poses"]["translation_max"], nlohmann::json::array({9.0, 12.0, 1.0}));
  EXPECT_EQ(j["bounds"]["max"], nlohmann::json::array({30.0, 0.0, 3.0}));
  EXPECT_EQ(j["time"]["last"], 0.75);
}

// A frame that cannot be read is counted and passed over, as `run` skips it;
// a sequence with no readable frame is an error naming the first failure.
TEST(CliInfo, UnreadableFramesAreCountedAndPassedOver) {
  test::ScratchFolder dir;
  const std::string good =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n0 0 1\n1 0 1\n";
  const std::string truncated = good.substr(0, good.size() - 6);
  // A three-frame sequence of these PLY texts, all at the identity pose.
  const auto write_sequence = [&](const std::string& name, const std::array<std::string, 3>& plys) {
    return test::write_frame_sequence(dir, name, {{plys[0]}, {plys[1]}, {plys[2]}}).string();
  };

  const std::string one_bad = write_sequence("one_bad", {good, truncated, good});
  auto r = run_cli("info " + quoted(one_bad), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("frames: 2 (1 unreadable, the first: "));
  EXPECT_THAT(r.out, HasSubstr("b.ply"));
  EXPECT_THAT(r.out, HasSubstr("points: 4\n"));
  r = run_cli("info --json " + quoted(one_bad), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["frames"], 2);
  EXPECT_EQ(j["unreadable_frames"], 1);
  EXPECT_THAT(j["first_unreadable"].get<std::string>(), HasSubstr("b.ply"));

  // Two of three unreadable, then the third too.
  const std::string one_good = write_sequence("one_good", {truncated, good, truncated});
  r = run_cli("info --json " + quoted(one_good), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["unreadable_frames"], 2);
  dir.write("one_good/b.ply", truncated);
  r = run_cli("info " + quoted(one_good), dir.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "");
  EXPECT_THAT(r.err, HasSubstr("none of the 3 frames could be read; the first: "));
  EXPECT_THAT(r.err, HasSubstr("a.ply"));
}

TEST(CliInfo, ErrorsGoToStderrWithANonZeroExit) {
  test::ScratchFolder dir;
  auto r = run_cli("info " + quoted((dir / "absent.ply").string()), dir.path());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.out, "");
  EXPECT_THAT(r.err, HasSubstr("sarmap: error: "));
  EXPECT_THAT(r.err, HasSubstr("absent.ply"));

  r = run_cli("info " + quoted(kData + "/bad/bad_sequence_unknown_key"), dir.path());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("sequence.json: frames[0]: unknown key \"posee\""));
  r = run_cli("info " + quoted(kData + "/bad/bad_sequence_version"), dir.path());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("version: unsupported sequence version 2"));
  r = run_cli("info " + quoted(dir.path().string()), dir.path());  // holds only the captured output files
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("not a recognised scan sequence"));
}

TEST(CliInfo, TumFolderNeedsIntrinsicsAndReportsSkippedFrames) {
  test::ScratchFolder dir;
  std::filesystem::create_directories(dir / "tum/depth");
  for (int f = 0; f < 3; ++f) {
    test::write_png_gray16(dir / ("tum/depth/" + std::to_string(f) + ".png"), 2, 2, {5000, 0, 10000, 5000});
  }
  dir.write("tum/depth.txt", "# timestamp filename\n1.00 depth/0.png\n1.10 depth/1.png\n1.90 depth/2.png\n");
  dir.write("tum/groundtruth.txt", "1.00 0 0 0 0 0 0 1\n1.11 1 0 0 0 0 0 1\n");
  const auto k = dir.write("k.txt", "100 0 0.5\n0 100 0.5\n0 0 1\n");
  auto r = run_cli("info " + quoted((dir / "tum").string()), dir.path());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("--intrinsics"));
  r = run_cli("info --intrinsics " + quoted(k.string()) + " " + quoted((dir / "tum").string()), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("layout: tum"));
  EXPECT_THAT(r.out, HasSubstr("frames: 2 (1 more skipped: no pose within 0.02 s)"));
  EXPECT_THAT(r.out, HasSubstr("points: 6\n"));
  EXPECT_THAT(r.out, HasSubstr("path length 1.000 m"));
}

}  // namespace
}  // namespace sarmap
