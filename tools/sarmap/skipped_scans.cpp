#include "tools/sarmap/skipped_scans.hpp"

#include <cstdio>

namespace sarmap::cli {

void SkippedScans::add(std::size_t scan, const std::string& source, const Error& error, bool row_open) {
  if (strict_) throw Error(error.code(), std::string(error.what()) + " (--strict: a bad scan ends the run)");
  profile_.skip_scan(scan, source, error.what(), row_open);
  const std::size_t skipped = count();
  if (skipped == 1) first_error_ = error.what();
  if (skipped <= kMaxWarnings) {
    std::fprintf(stderr, "\nsarmap: warning: skipped scan %zu: %s\n", scan, error.what());
  }
  if (skipped == kMaxWarnings + 1) {
    std::fprintf(stderr, "sarmap: warning: more scans skipped; all are listed in profile.json\n");
  }
}

}  // namespace sarmap::cli
