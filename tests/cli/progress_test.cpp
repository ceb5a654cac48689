#include "tools/sarmap/progress.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <unistd.h>
#include <cstdio>
#include <string>

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

TEST(Progress, IsSilentWhenDisabled) {
  // Disabled (as with --quiet): updates must not touch stderr; capture it to check.
  testing::internal::CaptureStderr();
  {
    ProgressLine line("x", 3, false);
    line.update(1);
    line.update(3);
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

}  // namespace
}  // namespace sarmap::cli
