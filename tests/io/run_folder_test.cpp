// Output folders as whole-or-absent sets: the manifest is removed first and
// written last with every output's size and hash, readers refuse a folder that
// does not match it, one writer at a time, temporaries of dead writers swept.
#include "engine/io/run_folder.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "engine/io/sha256.hpp"
#include "tests/io/error_message.hpp"
#include "tests/io/scratch_folder.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// A pid that belonged to a process which has exited and been reaped.
pid_t pid_of_a_finished_process() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

class RunFolderTest : public ::testing::Test {
 protected:
  // A committed set of two outputs in folder "run".
  fs::path committed_run() {
    const fs::path run = scratch_ / "run";
    RunFolderWriter writer(run);
    scratch_.write("run/a.txt", "alpha");
    scratch_.write("run/b.bin", std::string(1000, 'b'));
    writer.commit(Json{{"scans", 3}}, {"a.txt", "b.bin"});
    return run;
  }
  test::ScratchFolder scratch_;
};

TEST_F(RunFolderTest, ManifestListsEachOutputWithSizeAndHash) {
  const fs::path run = committed_run();
  const Json manifest = Json::parse(std::ifstream(run / "manifest.json"));
  EXPECT_EQ(manifest.at("scans").get<int>(), 3);
  ASSERT_EQ(manifest.at("outputs").size(), 2u);
  EXPECT_EQ(manifest.at("outputs")[0].at("name").get<std::string>(), "a.txt");
  EXPECT_EQ(manifest.at("outputs")[0].at("bytes").get<int>(), 5);
  EXPECT_EQ(manifest.at("outputs")[0].at("sha256").get<std::string>(), sha256_hex("alpha"));
  EXPECT_EQ(manifest.at("outputs")[1].at("bytes").get<int>(), 1000);
  EXPECT_NO_THROW(verify_run_folder(run));
  // Files added later (a plan, a rendering) are not part of the set.
  scratch_.write("run/plan.json", "{}");
  EXPECT_NO_THROW(verify_run_folder(run));
}

TEST_F(RunFolderTest, ANewWriterWithdrawsTheOldSetAtOnce) {
  const fs::path run = committed_run();
  RunFolderWriter rerun(run);
  EXPECT_FALSE(fs::exists(run / "manifest.json"));
  test::expect_error([&] { verify_run_folder(run); }, ErrorCode::InvalidData, "no manifest.json");
}

TEST_F(RunFolderTest, ReadersNameTheFileThatDoesNotMatch) {
  const fs::path run = committed_run();
  scratch_.write("run/a.txt", "alphabet");  // another size
  test::expect_error([&] { verify_run_folder(run); }, ErrorCode::InvalidData, "a.txt: 8 bytes, manifest.json says 5");
  scratch_.write("run/a.txt", "alpha");
  scratch_.write("run/b.bin", std::string(999, 'b') + "c");  // same size, other bytes
  test::expect_error([&] { verify_run_folder(run); }, ErrorCode::InvalidData, "b.bin: its SHA-256 differs");
  fs::remove(run / "b.bin");
  test::expect_error([&] { verify_run_folder(run); }, ErrorCode::InvalidData,
                     "b.bin: listed in manifest.json but missing");
}

TEST_F(RunFolderTest, RefusesManifestsItCannotTrust) {
  const fs::path run = scratch_ / "run";
  fs::create_directories(run);
  scratch_.write("run/manifest.json", R"({"outputs": ["map.sarmap"]})");
  test::expect_error([&] { verify_run_folder(run); }, ErrorCode::InvalidData, "older");
  scratch_.write("run/manifest.json", R"({"outputs": [{"name": "../x", "bytes": 1, "sha256": "00"}]})");
  test::expect_error([&] { verify_run_folder(run); }, ErrorCode::InvalidData, "not a file name in the folder");
  scratch_.write("run/manifest.json", R"({"outputs": [{"name": "x"}]})");
  test::expect_error([&] { verify_run_folder(run); }, ErrorCode::InvalidData, "lacks its name, bytes or sha256");
  scratch_.write("run/manifest.json", "{not json");
  test::expect_error([&] { verify_run_folder(run); }, ErrorCode::InvalidData, "not a JSON object");
}

TEST_F(RunFolderTest, OneWriterAtATime) {
  const fs::path run = scratch_ / "run";
  {
    RunFolderWriter first(run);
    test::expect_invalid_argument([&] { RunFolderWriter second(run); },
                                  "another sarmap process (pid " + std::to_string(::getpid()) + ")");
  }
  EXPECT_NO_THROW(RunFolderWriter again(run));  // the lock goes with its writer
}

TEST_F(RunFolderTest, RefusesRootsFilesAndOtherPeoplesFolders) {
  test::expect_invalid_argument([] { RunFolderWriter w("/"); }, "filesystem root");
  const auto file = scratch_.write("a_file", "x");
  test::expect_invalid_argument([&] { RunFolderWriter w(file); }, "is not a folder");
  scratch_.write("photos/holiday.jpg", "x");
  test::expect_invalid_argument([&] { RunFolderWriter w(scratch_ / "photos"); }, "holds other files");
  EXPECT_TRUE(fs::exists(scratch_ / "photos" / "holiday.jpg"));
  fs::create_directories(scratch_ / "empty");
  EXPECT_NO_THROW(RunFolderWriter w(scratch_ / "empty"));
  // A folder an interrupted run left (outputs, no manifest) is taken again.
  scratch_.write("interrupted/map.sarmap", "x");
  EXPECT_NO_THROW(RunFolderWriter w(scratch_ / "interrupted"));
}

TEST_F(RunFolderTest, SweepsTemporariesOfWritersThatAreGone) {
  const fs::path run = committed_run();
  const std::string dead = ".map.sarmap.tmp." + std::to_string(pid_of_a_finished_process()) + ".17";
  const std::string alive = ".map.bt.tmp." + std::to_string(::getpid()) + ".18";
  scratch_.write("run/" + dead, "half a map");
  scratch_.write("run/" + alive, "being written");
  scratch_.write("run/.notes.tmp.x.1", "not ours: no pid");
  RunFolderWriter rerun(run);
  EXPECT_FALSE(fs::exists(run / dead));
  EXPECT_TRUE(fs::exists(run / alive));
  EXPECT_TRUE(fs::exists(run / ".notes.tmp.x.1"));
}

TEST_F(RunFolderTest, CommitNamesAMissingOutput) {
  RunFolderWriter writer(scratch_ / "run");
  test::expect_error([&] { writer.commit(Json::object(), {"never_written.ply"}); }, ErrorCode::Io,
                     "never_written.ply: output missing");
  EXPECT_FALSE(fs::exists(scratch_ / "run" / "manifest.json"));
}

}  // namespace
}  // namespace sarmap
