// `sarmap run --checkpoint-every N --resume`: runs killed with SIGKILL at
// random moments (a fixed seed, a bounded number of trials) and resumed end
// with outputs equal to an uninterrupted run's, byte for byte (profile.json,
// summary.json and the manifest that hashes them aside: they hold timings),
// and no kill ever leaves an output folder that reads as whole but is not.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/io/run_folder.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/release_only.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::read_all;
using test::run_cli;

const std::vector<std::string> kCompared = {
    "map.sarmap",          "map.bt",        "map.ot",       "voxels.ply",
    "semantic_points.ply", "segments.json", "segments.ply", "graph.json",
    "graph.graphml",       "graph.ply",     "grid.pgm",     "grid.yaml"};

class RunResume : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sequence_ = new test::ScratchFolder();
    const auto r = run_cli("simulate " + quoted(std::string(SARMAP_SOURCE_DIR) + "/datasets/arenas/esogu-6x4.json") +
                               " --out " + quoted((*sequence_ / "seq").string()) + " --frames 48 --quiet",
                           sequence_->path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete sequence_;
    sequence_ = nullptr;
  }

  std::vector<std::string> run_args(const fs::path& out, const std::string& extra) const {
    std::vector<std::string> args = {SARMAP_CLI_PATH, "run", (*sequence_ / "seq").string(), "--out", out.string(),
                                     "--classifier", "labels", "--quiet"};
    std::size_t start = 0;
    while (start < extra.size()) {
      const std::size_t end = extra.find(' ', start);
      args.push_back(extra.substr(start, end - start));
      start = end == std::string::npos ? extra.size() : end + 1;
    }
    return args;
  }

  // Starts the run as a child process; returns its pid.
  pid_t spawn(const std::vector<std::string>& args) const {
    const pid_t pid = ::fork();
    if (pid == 0) {
      std::vector<char*> argv;
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      const std::string log = (scratch_ / "child.log").string();
      if (std::freopen(log.c_str(), "a", stdout) == nullptr || std::freopen(log.c_str(), "a", stderr) == nullptr) {
        ::_exit(126);
      }
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    return pid;
  }

  // Exit code, or -signal.
  static int wait_for(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }

  int run_to_end(const fs::path& out, const std::string& extra) const { return wait_for(spawn(run_args(out, extra))); }

  // A folder with a manifest must be the whole set it lists.
  static void expect_whole_or_unfinished(const fs::path& out) {
    if (!fs::exists(out / "manifest.json")) return;
    EXPECT_NO_THROW(verify_run_folder(out)) << out;
  }

  static void expect_same_outputs(const fs::path& a, const fs::path& b) {
    for (const std::string& name : kCompared) {
      EXPECT_TRUE(read_all(a / name) == read_all(b / name)) << name << " differs between " << a << " and " << b;
    }
    // summary.json's figures too, but for its timings and the bytes of the
    // maps and the kept points: a resumed run packs them afresh from the
    // checkpoint, without the storage the uninterrupted one keeps for reuse
    // or has grown into (docs/formats.md).
    const auto figures = [](const fs::path& folder) {
      auto summary = nlohmann::json::parse(read_all(folder / "summary.json"));
      for (const char* timing : {"wall_s", "scans_per_second", "stages", "latency"}) summary.erase(timing);
      summary.at("metric_map").erase("bytes");
      summary.erase("semantic_points_bytes");
      summary.at("segments").erase("bytes");
      summary.at("topo_map").erase("bytes");
      summary.at("topo_map").erase("embree_bytes");
      return summary;
    };
    EXPECT_EQ(figures(a), figures(b)) << "summary.json differs between " << a << " and " << b;
  }

  static test::ScratchFolder* sequence_;
  test::ScratchFolder scratch_;
};

test::ScratchFolder* RunResume::sequence_ = nullptr;

TEST_F(RunResume, CheckpointsChangeNothingAndAreRemovedAtTheEnd) {
  const fs::path reference = scratch_ / "reference", checkpointed = scratch_ / "checkpointed";
  ASSERT_EQ(run_to_end(reference, ""), 0);
  ASSERT_EQ(run_to_end(checkpointed, "--checkpoint-every 5"), 0);
  expect_same_outputs(reference, checkpointed);
  EXPECT_FALSE(fs::exists(checkpointed / ".checkpoint"));
  // --resume without a checkpoint starts from the first frame.
  const fs::path fresh = scratch_ / "fresh";
  ASSERT_EQ(run_to_end(fresh, "--resume"), 0);
  expect_same_outputs(reference, fresh);
}

// Snapshots ride along: a resumed run keeps those written before its
// checkpoint and writes the rest, all equal to an uninterrupted run's.
TEST_F(RunResume, KilledRunsResumeToTheUninterruptedOutputs) {
  const fs::path reference = scratch_ / "reference";
  const std::string snapshots = "--snapshots 12,30";
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(run_to_end(reference, snapshots), 0);
  const double run_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::mt19937 random(20261126);
  std::uniform_real_distribution<double> moment(0.0, 1.1 * run_s);
  constexpr int kTrials = kSanitizedBuild ? 2 : 4, kKillsPerTrial = 3;
  int killed = 0, resumed_from_a_checkpoint = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const fs::path out = scratch_ / ("trial" + std::to_string(trial));
    for (int kill = 0; kill < kKillsPerTrial; ++kill) {
      resumed_from_a_checkpoint += fs::exists(out / ".checkpoint" / "state.bin");
      const pid_t pid = spawn(run_args(out, "--checkpoint-every 3 --resume " + snapshots));
      std::this_thread::sleep_for(std::chrono::duration<double>(moment(random)));
      ::kill(pid, SIGKILL);
      killed += wait_for(pid) == -SIGKILL;
      expect_whole_or_unfinished(out);
      expect_whole_or_unfinished(out / "snap_0012");
      expect_whole_or_unfinished(out / "snap_0030");
    }
    ASSERT_EQ(run_to_end(out, "--checkpoint-every 3 --resume " + snapshots), 0) << read_all(scratch_ / "child.log");
    verify_run_folder(out);
    expect_same_outputs(reference, out);
    for (const char* snapshot : {"snap_0012", "snap_0030"}) {
      verify_run_folder(out / snapshot);
      expect_same_outputs(reference / snapshot, out / snapshot);
    }
  }
  // The moments must have hit running processes, and some resumes started
  // from a checkpoint, or the test proved little.
  EXPECT_GE(killed, kTrials);
  EXPECT_GE(resumed_from_a_checkpoint, 2);
}

TEST_F(RunResume, ACheckpointOfOtherSettingsIsRefused) {
  const fs::path out = scratch_ / "run";
  const pid_t pid = spawn(run_args(out, "--checkpoint-every 1"));
  // Wait for a checkpoint, then stop the run.
  for (int i = 0; i < 3000 && !fs::exists(out / ".checkpoint" / "state.bin"); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid, SIGKILL);
  wait_for(pid);
  ASSERT_TRUE(fs::exists(out / ".checkpoint" / "state.bin"));
  const auto r = run_cli("run " + quoted((*sequence_ / "seq").string()) + " --out " + quoted(out.string()) +
                             " --classifier labels --voxel 0.1 --resume --quiet",
                         scratch_.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("other settings or input"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("without --resume"), std::string::npos) << r.err;
  // Without --resume the same command starts over and drops the old checkpoint.
  const auto again = run_cli("run " + quoted((*sequence_ / "seq").string()) + " --out " + quoted(out.string()) +
                                 " --classifier labels --voxel 0.1 --quiet",
                             scratch_.path());
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_FALSE(fs::exists(out / ".checkpoint"));
}

}  // namespace
}  // namespace sarmap
