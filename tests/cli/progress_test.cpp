#include "tools/sarmap/progress.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

#include "tests/cli/cli_runner.hpp"

namespace sarmap::cli {
namespace {

TEST(Progress, FormatsCountRateAndEta) {
  EXPECT_EQ(format_progress("convert", 0, 340, 0.0), "convert: 0/340 frames");
  EXPECT_EQ(format_progress("convert", 12, 340, 2.0), "convert: 12/340 frames  6.0 frames/s  ETA 0:55");
  EXPECT_EQ(format_progress("info", 340, 340, 10.0), "info: 340/340 frames  34.0 frames/s");
  EXPECT_EQ(format_progress("info", 5, 0, 1.0), "info: 5 frames  5.0 frames/s");
}

TEST(Progress, FormatsDurations) {
  EXPECT_EQ(format_duration(0.4), "0:00");
  EXPECT_EQ(format_duration(7), "0:07");
  EXPECT_EQ(format_duration(725), "12:05");
  EXPECT_EQ(format_duration(3723), "1:02:03");
  EXPECT_EQ(format_duration(-3), "0:00");
}

// Everything the terminal received so far.
std::string drain(int master) {
  std::string out;
  char buffer[512];
  pollfd p{master, POLLIN, 0};
  while (::poll(&p, 1, 200) > 0) {
    const ssize_t n = ::read(master, buffer, sizeof buffer);
    if (n <= 0) break;
    out.append(buffer, static_cast<std::size_t>(n));
  }
  return out;
}

TEST(Progress, DrawsInPlaceOnATerminalAndClearsAtTheEnd) {
  int master = -1, slave = -1;
  ASSERT_EQ(::openpty(&master, &slave, nullptr, nullptr, nullptr), 0);
  std::FILE* terminal = ::fdopen(slave, "w");
  ASSERT_NE(terminal, nullptr);
  {
    ProgressLine line("convert", 3, true, terminal);
    line.update(1);
    line.update(3);  // the last frame is always drawn
    const std::string drawn = drain(master);
    EXPECT_THAT(drawn, ::testing::StartsWith("\rconvert: 1/3 frames"));
    EXPECT_THAT(drawn, ::testing::HasSubstr("\rconvert: 3/3 frames"));
    EXPECT_EQ(drawn.find('\n'), std::string::npos);
  }
  const std::string cleared = drain(master);
  ASSERT_FALSE(cleared.empty());
  EXPECT_EQ(cleared.front(), '\r');
  EXPECT_EQ(cleared.back(), '\r');
  EXPECT_EQ(cleared.find_first_not_of(" \r"), std::string::npos);
  std::fclose(terminal);
  ::close(master);

  std::FILE* file = std::tmpfile();
  EXPECT_FALSE(is_terminal(file));
  std::fclose(file);
}

// On a terminal, where an enabled line does draw (the test above), a
// disabled one (--quiet) must not.
TEST(Progress, IsSilentWhenDisabled) {
  int master = -1, slave = -1;
  ASSERT_EQ(::openpty(&master, &slave, nullptr, nullptr, nullptr), 0);
  std::FILE* terminal = ::fdopen(slave, "w");
  ASSERT_NE(terminal, nullptr);
  ASSERT_TRUE(is_terminal(terminal));
  {
    ProgressLine line("x", 3, false, terminal);
    line.update(1);
    line.update(3);
    line.finish();
  }
  std::fflush(terminal);
  EXPECT_EQ(drain(master), "");
  std::fclose(terminal);
  ::close(master);
}

// The whole CLI on a pseudo-terminal, as a user at a shell sees it: `sarmap
// run` draws its progress line there, and --quiet removes it.
std::string cli_on_a_terminal(const std::string& args) {
  int master = -1;
  const pid_t child = ::forkpty(&master, nullptr, nullptr, nullptr);
  if (child == 0) {
    const std::string command = std::string("exec '") + SARMAP_CLI_PATH + "' " + args;
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::string out;
  char buffer[512];
  while (true) {
    const ssize_t n = ::read(master, buffer, sizeof buffer);
    if (n <= 0) break;  // EIO once the child has exited and closed the terminal
    out.append(buffer, static_cast<std::size_t>(n));
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ::close(master);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;
  return out;
}

TEST(Progress, RunDrawsOnATerminalUnlessQuiet) {
  const std::string tmp = ::testing::TempDir() + "sarmap_progress_pty_" + std::to_string(::getpid());
  const std::string run = std::string("run '") + SARMAP_TEST_DATA_DIR + "/sequences/tiny' --classifier labels --voxel 0.1 --out '" + tmp;
  const std::string loud = cli_on_a_terminal(run + "/loud'");
  EXPECT_THAT(loud, ::testing::HasSubstr("\rrun: 2/2 frames"));
  const std::string quiet = cli_on_a_terminal(run + "/quiet' --quiet");
  EXPECT_EQ(quiet.find("frames"), std::string::npos) << quiet;
  EXPECT_EQ(quiet, "");
  std::filesystem::remove_all(tmp);
}

// `sarmap simulate` the same way: its progress line draws on a terminal only.
TEST(Progress, SimulateDrawsOnATerminalUnlessQuiet) {
  const std::string tmp = ::testing::TempDir() + "sarmap_progress_sim_pty_" + std::to_string(::getpid());
  const std::string simulate =
      std::string("simulate '") + SARMAP_SOURCE_DIR + "/tests/cli/data/tiny_arena.json' --out '" + tmp;
  const std::string loud = cli_on_a_terminal(simulate + "/loud'");
  EXPECT_THAT(loud, ::testing::HasSubstr("\rsimulate: 3/3 frames"));
  EXPECT_THAT(loud, ::testing::HasSubstr("tiny-3x2: 3 frames"));
  const std::string quiet = cli_on_a_terminal(simulate + "/quiet' --quiet");
  EXPECT_EQ(quiet, "");
  std::filesystem::remove_all(tmp);
}

// Off a terminal (a log, a pipe) simulate prints its one summary line and no
// line per frame.
TEST(Progress, SimulatePrintsNoLinePerFrameOffATerminal) {
  const std::filesystem::path tmp =
      std::filesystem::temp_directory_path() / ("sarmap_progress_sim_log_" + std::to_string(::getpid()));
  std::filesystem::create_directories(tmp);
  const auto r = test::run_cli(
      "simulate " + test::quoted(std::string(SARMAP_SOURCE_DIR) + "/tests/cli/data/tiny_arena.json") + " --out " +
          test::quoted((tmp / "sequence").string()),
      tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_THAT(r.out, ::testing::StartsWith("tiny-3x2: 3 frames, "));
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  std::filesystem::remove_all(tmp);
}

}  // namespace
}  // namespace sarmap::cli
