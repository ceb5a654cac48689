// The command-line options that say how to open a scan sequence (intrinsics
// for depth-image layouts, TUM's pose-matching tolerance), declared once for
// every command that reads sequences: info, convert, run and classify.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "engine/io/scan_source.hpp"

namespace sarmap::cli {

struct SequenceInputArgs {
  std::string intrinsics;  // empty: intrinsics.json / camera-intrinsics.txt in the folder
  double max_time_difference = ScanSequenceOptions{}.max_time_difference;
  double max_file_mb = static_cast<double>(InputLimits{}.max_file_bytes >> 20);
  std::size_t max_scan_points = InputLimits{}.max_points;

  ScanSequenceOptions options() const;
};

// Adds --intrinsics, --max-time-difference, --max-file-mb and
// --max-scan-points to cmd, bound to args.
void add_sequence_input_options(CLI::App* cmd, SequenceInputArgs& args);

}  // namespace sarmap::cli
