// `sarmap run` with one bad scan in a sequence: a truncated frame, a pose
// beyond the map's limits, a point far beyond any sensor's range. The scan is
// skipped with a warning and listed in profile.json (--strict makes it fatal);
// a run in which no scan can be used is an error.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/metric/semantic_blocks.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/cli/frame_sequence.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/semantic/fixture_model.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::run_cli;

constexpr const char* kIdentity = test::kIdentityPose;
constexpr const char* kGoodFrame =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar label\nend_header\n0 0 1 1\n1 0 1 2\n0 1 1 2\n";

class RunFaults : public ::testing::Test {
 protected:
  // A sequence of three frames whose middle one is `middle` at `middle_pose`.
  fs::path sequence(const std::string& middle, const std::string& middle_pose = kIdentity) {
    return test::write_frame_sequence(scratch_, "seq", {{kGoodFrame}, {middle, middle_pose}, {kGoodFrame}});
  }
  test::CliResult run(const fs::path& input, const std::string& extra = "") {
    return run_cli("run " + quoted(input.string()) + " --out " + quoted(out().string()) +
                       " --voxel 0.1 --classifier labels --quiet" + extra,
                   scratch_.path());
  }
  fs::path out() const { return scratch_ / "run"; }
  nlohmann::json profile() const { return nlohmann::json::parse(test::read_all(out() / "profile.json")); }
  test::ScratchFolder scratch_;
};

TEST_F(RunFaults, ATruncatedFrameIsSkippedNamedAndCounted) {
  const std::string truncated = std::string(kGoodFrame).substr(0, std::string(kGoodFrame).size() - 12);
  const fs::path input = sequence(truncated);
  auto r = run(input);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("sarmap: warning: skipped scan 1: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("b.ply"), std::string::npos) << r.err;
  const auto p = profile();
  EXPECT_EQ(p.at("scans").get<int>(), 2);
  EXPECT_EQ(p.at("per_scan").size(), 2u);
  EXPECT_EQ(p.at("skipped_scans").get<int>(), 1);
  EXPECT_EQ(p.at("skipped").at(0).at("scan").get<int>(), 1);
  EXPECT_NE(p.at("skipped").at(0).at("error").get<std::string>().find("b.ply"), std::string::npos);
  const auto manifest = nlohmann::json::parse(test::read_all(out() / "manifest.json"));
  EXPECT_EQ(manifest.at("scans").get<int>(), 2);
  EXPECT_EQ(manifest.at("scans_skipped").get<int>(), 1);

  r = run(input, " --strict");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("b.ply"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--strict"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out() / "manifest.json"));  // the earlier run's set is withdrawn, not mixed
}

TEST_F(RunFaults, APoseBeyondTheMapIsSkippedNamingTheScan) {
  const fs::path input = sequence(kGoodFrame, "[1,0,0,1e7, 0,1,0,0, 0,0,1,0, 0,0,0,1]");
  auto r = run(input);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("skipped scan 1: scan 1 ("), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("map limits"), std::string::npos) << r.err;
  EXPECT_EQ(profile().at("skipped_scans").get<int>(), 1);
  r = run(input, " --strict");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("b.ply"), std::string::npos) << r.err;
}

// One outlier 1e30 m out (a sensor glitch) is dropped and counted, not fatal
// and not stretching the classifier's blocks over the whole distance.
TEST_F(RunFaults, FarPointsAreDroppedAndCounted) {
  const std::string frame = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                            "property float z\nproperty uchar label\nend_header\n0 0 1 1\n1 0 1 1\n0 1 1 1\n"
                            "1e30 0 1 2\n";
  const fs::path input = sequence(frame);
  const std::string model = test::fixture_model_c6().string();
  auto r = run_cli("run " + quoted(input.string()) + " --out " + quoted(out().string()) +
                       " --voxel 0.1 --quiet --min-block-points 1 --model " + quoted(model),
                   scratch_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto p = profile();
  EXPECT_EQ(p.at("skipped_scans").get<int>(), 0);
  EXPECT_EQ(p.at("stages").at("preprocess").at("points_far").get<double>(), 1.0);
  EXPECT_EQ(p.at("stages").at("preprocess").at("points_out").get<double>(), 9.0);
  // The limit is a setting: 0 keeps every point (the metric map still rejects the far one).
  r = run(input, " --max-point-distance 0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(profile().at("stages").at("preprocess").at("points_out").get<double>(), 10.0);
  r = run(input, " --max-point-distance nan");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--max-point-distance"), std::string::npos) << r.err;
}

TEST_F(RunFaults, ARunWithNoUsableScanIsAnError) {
  scratch_.write("seq/a.ply", "ply\nformat ascii 1.0\nelement vertex 3\n");
  scratch_.write("seq/sequence.json",
                 std::string(R"({"version": 1, "points_frame": "world", "frames": [{"file": "a.ply", "pose": )") + kIdentity + "}]}");
  const auto r = run(scratch_ / "seq");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("none of the 1 scans could be used; the first: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("a.ply"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out() / "manifest.json"));
}

// A frame over the input limits is one bad frame: skipped, named, counted.
TEST_F(RunFaults, AFrameOverTheInputLimitsIsSkippedNamingTheLimit) {
  const std::string big = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                          "property float z\nproperty uchar label\nend_header\n0 0 1 1\n1 0 1 2\n0 1 1 2\n"
                          "1 1 1 2\n2 1 1 2\n";
  const fs::path input = sequence(big);
  auto r = run(input, " --max-scan-points 4");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("b.ply: the header declares 5 points, more than the limit of 4"), std::string::npos) << r.err;
  EXPECT_EQ(profile().at("skipped_scans").get<int>(), 1);
  r = run(input, " --max-file-mb 0.0001");  // 104 bytes: every frame is larger
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("more than the limit of 104 bytes"), std::string::npos) << r.err;
  for (const char* bad : {" --max-file-mb 0", " --max-file-mb nan", " --max-scan-points 0", " --max-scan-points -1"}) {
    r = run(input, bad);
    EXPECT_NE(r.exit_code, 0) << bad;
    EXPECT_NE(r.err.find(std::string(bad).substr(1, std::string(bad).find(' ', 1) - 1)), std::string::npos)
        << bad << ": " << r.err;
  }
}

// By default the map keeps as many blocks as half the machine's memory holds.
TEST_F(RunFaults, TheMapBlockBudgetDefaultsToHalfTheMemory) {
  ASSERT_EQ(run(sequence(kGoodFrame)).exit_code, 0);
  const auto manifest = nlohmann::json::parse(test::read_all(out() / "manifest.json"));
  const auto budget = manifest.at("config").at("bounds").at("max_blocks").get<std::size_t>();
  const std::size_t memory = static_cast<std::size_t>(::sysconf(_SC_PHYS_PAGES)) * ::sysconf(_SC_PAGE_SIZE);
  EXPECT_GT(budget, 0u);
  // A block at its largest: its record, a slab of 512 log-odds, a row of
  // evidence for every voxel and its share of the key table.
  EXPECT_NEAR(static_cast<double>(budget) * metric::SemanticBlocks::kMaxBlockBytes, memory / 2.0,
              memory * 0.01);
  EXPECT_GT(metric::SemanticBlocks::kMaxBlockBytes, 512u * (1 + 6));
}

}  // namespace
}  // namespace sarmap
