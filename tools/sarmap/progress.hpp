// The progress line of long CLI commands: frames done / total, rate and ETA,
// redrawn in place with a carriage return on stderr. It stays silent when
// stderr is not a terminal (logs, pipes, tests) or when the user asked --quiet.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace sarmap::cli {

// "label: 12/340 frames  25.3 frames/s  ETA 0:13" (no rate or ETA before the
// first frame; total 0 means unknown). Pure, so it can be tested.
std::string format_progress(std::string_view label, std::size_t done, std::size_t total, double elapsed_s);

// "0:07", "12:05", "1:02:03".
std::string format_duration(double seconds);

bool is_terminal(std::FILE* stream);

class ProgressLine {
 public:
  // Draws only when `enabled` (typically !quiet) and `stream` is a terminal.
  ProgressLine(std::string label, std::size_t total, bool enabled, std::FILE* stream = stderr);
  // Clears the line, so later output starts at column 0.
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // Redraws at most ten times per second, and always for the last frame.
  void update(std::size_t done);
  void finish();

 private:
  std::string label_;
  std::size_t total_;
  std::FILE* stream_;
  bool active_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::size_t drawn_width_ = 0;
};

}  // namespace sarmap::cli
