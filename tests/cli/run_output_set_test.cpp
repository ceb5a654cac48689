// `sarmap run`'s output folder is one set, whole or absent: a run that fails
// while writing leaves no manifest and the readers (eval, plan) refuse the
// folder; a second run cannot write a folder another is writing; a folder
// that is a root or holds other files is refused before any mapping.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "tests/cli/cli_runner.hpp"
#include "tests/io/scratch_folder.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::run_cli;

class RunOutputSet : public ::testing::Test {
 protected:
  test::CliResult run(const fs::path& out) {
    return run_cli("run " + quoted(input_.string()) + " --out " + quoted(out.string()) +
                       " --voxel 0.1 --classifier labels --quiet",
                   scratch_.path());
  }
  test::CliResult plan(const fs::path& out) {
    return run_cli("plan " + quoted(out.string()) + " --from 0,0,0 --to 1,1,0 --quiet", scratch_.path());
  }
  test::ScratchFolder scratch_;
  const fs::path input_ = fs::path(SARMAP_TEST_DATA_DIR) / "sequences" / "tiny";
};

TEST_F(RunOutputSet, AFailureWhileWritingLeavesAFolderReadersRefuse) {
  const fs::path out = scratch_ / "run";
  ASSERT_EQ(run(out).exit_code, 0);
  ASSERT_EQ(plan(out).exit_code, 0);
  // A rerun whose graph.json cannot be written (a folder stands in its place)
  // fails after map.sarmap is already new: that folder must not read as a run.
  fs::remove(out / "graph.json");
  fs::create_directories(out / "graph.json" / "blocker");
  const auto r = run(out);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("graph.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "manifest.json"));
  const auto p = plan(out);
  EXPECT_EQ(p.exit_code, 1);
  EXPECT_NE(p.err.find("no manifest.json"), std::string::npos) << p.err;
  // Nothing of the failed run's temporaries stays behind.
  for (const auto& entry : fs::directory_iterator(out)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << entry.path();
  }
  fs::remove_all(out / "graph.json");
  EXPECT_EQ(run(out).exit_code, 0);
  EXPECT_EQ(plan(out).exit_code, 0);
}

TEST_F(RunOutputSet, AnOutputChangedAfterTheRunIsNamed) {
  const fs::path out = scratch_ / "run";
  ASSERT_EQ(run(out).exit_code, 0);
  const fs::path other = scratch_ / "other";
  ASSERT_EQ(run_cli("run " + quoted(input_.string()) + " --out " + quoted(other.string()) +
                        " --voxel 0.2 --classifier labels --quiet",
                    scratch_.path())
                .exit_code,
            0);
  fs::copy_file(other / "map.sarmap", out / "map.sarmap", fs::copy_options::overwrite_existing);
  const auto p = plan(out);
  EXPECT_EQ(p.exit_code, 1);
  EXPECT_NE(p.err.find("map.sarmap"), std::string::npos) << p.err;
}

TEST_F(RunOutputSet, OneRunAtATimePerFolder) {
  const fs::path out = scratch_ / "run";
  fs::create_directories(out);
  // Another process holds the folder's lock as a running `sarmap run` would.
  const int fd = ::open((out / ".sarmap.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const auto r = run(out);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("another sarmap process"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "map.sarmap"));
  ::close(fd);
  EXPECT_EQ(run(out).exit_code, 0);
}

TEST_F(RunOutputSet, RootsAndOtherFoldersAreRefusedBeforeMapping) {
  auto r = run("/");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("filesystem root"), std::string::npos) << r.err;
  scratch_.write("documents/report.txt", "mine");
  r = run(scratch_ / "documents");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("holds other files"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(scratch_ / "documents" / "map.sarmap"));
}

}  // namespace
}  // namespace sarmap
