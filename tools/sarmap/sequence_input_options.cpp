#include "tools/sarmap/sequence_input_options.hpp"

#include "tools/sarmap/number_checks.hpp"

namespace sarmap::cli {

ScanSequenceOptions SequenceInputArgs::options() const {
  ScanSequenceOptions options;
  if (!intrinsics.empty()) options.intrinsics_file = intrinsics;
  options.max_time_difference = max_time_difference;
  return options;
}

void add_sequence_input_options(CLI::App* cmd, SequenceInputArgs& args) {
  cmd->add_option("--intrinsics", args.intrinsics,
                  "Depth-camera intrinsics for TUM / 7-Scenes: JSON {fx, fy, cx, cy} or a 3x3 matrix as text");
  cmd->add_option("--max-time-difference", args.max_time_difference,
                  "TUM: largest gap in seconds between a depth frame and its ground-truth pose")
      ->capture_default_str()
      ->check(finite_non_negative());
}

}  // namespace sarmap::cli
