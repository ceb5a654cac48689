// The scans a run skips instead of failing (a frame that cannot be read, a
// scan the Mapper refuses): each is warned about on stderr (the first few)
// and recorded in profile.json; with --strict the first one ends the run.
#pragma once

#include <cstddef>
#include <string>

#include "engine/core/error.hpp"
#include "engine/core/stage_profile.hpp"

namespace sarmap::cli {

class SkippedScans {
 public:
  SkippedScans(StageProfile& profile, bool strict) : profile_(profile), strict_(strict) {}

  // Rethrows `error` under --strict; otherwise warns and records it.
  // `row_open`: the scan already has its profile row, which is dropped.
  void add(std::size_t scan, const std::string& source, const Error& error, bool row_open);

  std::size_t count() const { return profile_.skipped_scans(); }
  const std::string& first_error() const { return first_error_; }

 private:
  static constexpr std::size_t kMaxWarnings = 10;

  StageProfile& profile_;
  bool strict_;
  std::string first_error_;
};

}  // namespace sarmap::cli
