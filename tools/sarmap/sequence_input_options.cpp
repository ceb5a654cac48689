#include "tools/sarmap/sequence_input_options.hpp"

#include <cstdint>

#include "tools/sarmap/number_checks.hpp"

namespace sarmap::cli {

ScanSequenceOptions SequenceInputArgs::options() const {
  ScanSequenceOptions options;
  if (!intrinsics.empty()) options.intrinsics_file = intrinsics;
  options.max_time_difference = max_time_difference;
  // Past 2^64 bytes the cast would be undefined: any such limit means none.
  const double bytes = max_file_mb * 1024 * 1024;
  options.limits.max_file_bytes = bytes >= 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(bytes);
  options.limits.max_points = max_scan_points;
  return options;
}

void add_sequence_input_options(CLI::App* cmd, SequenceInputArgs& args) {
  cmd->add_option("--intrinsics", args.intrinsics,
                  "Depth-camera intrinsics for TUM / 7-Scenes: JSON {fx, fy, cx, cy} or a 3x3 matrix as text");
  cmd->add_option("--max-time-difference", args.max_time_difference,
                  "TUM: largest gap in seconds between a depth frame and its ground-truth pose")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--max-file-mb", args.max_file_mb,
                  "Refuse an input file (a frame, a cloud, a depth image) larger than this many MiB, before "
                  "reading it")
      ->capture_default_str()
      ->check(finite_positive());
  cmd->add_option("--max-scan-points", args.max_scan_points,
                  "Refuse a frame or cloud of more points (a header's count, a depth image's pixels), before "
                  "allocating for it")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
}

}  // namespace sarmap::cli
