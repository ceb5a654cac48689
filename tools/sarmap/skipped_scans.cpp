#include "tools/sarmap/skipped_scans.hpp"

#include <cstdio>

namespace sarmap::cli {

void SkippedScans::add(std::size_t scan, const std::string& source, const Error& error, bool row_open) {
  if (strict_) throw Error(error.code(), std::string(error.what()) + " (--strict: a bad scan ends the run)");
  profile_.skip_scan(scan, source, error.what(), row_open);
  if (count_ == 0) first_error_ = error.what();
  ++count_;
  if (count_ <= kMaxWarnings) {
    std::fprintf(stderr, "\nsarmap: warning: skipped scan %zu: %s\n", scan, error.what());
  }
  if (count_ == kMaxWarnings + 1) {
    std::fprintf(stderr, "sarmap: warning: more scans skipped; all are listed in profile.json\n");
  }
}

}  // namespace sarmap::cli
