#include "tools/sarmap/progress.hpp"

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sarmap::cli {

std::string format_duration(double seconds) {
  const long total = std::lround(std::max(0.0, seconds));
  const long h = total / 3600, m = (total / 60) % 60, s = total % 60;
  char text[32];
  if (h > 0) {
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", h, m, s);
  } else {
    std::snprintf(text, sizeof text, "%ld:%02ld", m, s);
  }
  return text;
}

std::string format_progress(std::string_view label, std::size_t done, std::size_t total, double elapsed_s) {
  std::string out(label);
  out += ": " + std::to_string(done);
  if (total > 0) out += "/" + std::to_string(total);
  out += " frames";
  if (done > 0 && elapsed_s > 0) {
    const double rate = static_cast<double>(done) / elapsed_s;
    char text[64];
    std::snprintf(text, sizeof text, "  %.1f frames/s", rate);
    out += text;
    if (total > done) out += "  ETA " + format_duration(static_cast<double>(total - done) / rate);
  }
  return out;
}

bool is_terminal(std::FILE* stream) { return ::isatty(::fileno(stream)) == 1; }

ProgressLine::ProgressLine(std::string label, std::size_t total, bool enabled, std::FILE* stream)
    : label_(std::move(label)),
      total_(total),
      stream_(stream),
      active_(enabled && is_terminal(stream)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

ProgressLine::~ProgressLine() { finish(); }

void ProgressLine::update(std::size_t done) {
  if (!active_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100) && done != total_) return;
  last_draw_ = now;
  const std::string line =
      format_progress(label_, done, total_, std::chrono::duration<double>(now - start_).count());
  // Pad over the remains of a longer previous line.
  const std::size_t pad = drawn_width_ > line.size() ? drawn_width_ - line.size() : 0;
  std::fprintf(stream_, "\r%s%*s", line.c_str(), static_cast<int>(pad), "");
  std::fflush(stream_);
  drawn_width_ = line.size();
}

void ProgressLine::finish() {
  if (!active_) return;
  if (drawn_width_ > 0) {
    std::fprintf(stream_, "\r%*s\r", static_cast<int>(drawn_width_), "");
    std::fflush(stream_);
  }
  active_ = false;
}

}  // namespace sarmap::cli
