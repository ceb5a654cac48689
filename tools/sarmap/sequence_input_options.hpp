// The command-line options that say how to open a scan sequence (intrinsics
// for depth-image layouts, the pose-matching tolerance of TUM and ROS bags, a
// bag's topics), declared once for every command that reads sequences: info,
// convert, run and classify; and open_input_sequence, which opens one.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "engine/io/scan_source.hpp"

namespace sarmap::cli {

struct SequenceInputArgs {
  std::string intrinsics;  // empty: intrinsics.json / camera-intrinsics.txt in the folder
  double max_time_difference = ScanSequenceOptions{}.max_time_difference;
  double max_file_mb = static_cast<double>(InputLimits{}.max_file_bytes >> 20);
  std::size_t max_scan_points = InputLimits{}.max_points;
  // ROS 1 bags (engine/io_rosbag/rosbag_sequence.hpp).
  std::string cloud_topic;
  std::string pose_topic;
  std::string fixed_frame;

  ScanSequenceOptions options() const;
};

// Adds --intrinsics, --max-time-difference, --max-file-mb, --max-scan-points,
// --cloud-topic, --pose-topic and --fixed-frame to cmd, bound to args.
void add_sequence_input_options(CLI::App* cmd, SequenceInputArgs& args);

// A path ending in ".bag" (any case): a ROS 1 bag, read as a sequence, not as a cloud file.
bool is_bag_path(const std::filesystem::path& path);

// A ROS 1 bag (.bag) through engine/io_rosbag when sarmap was built with it;
// anything else through open_scan_sequence.
std::unique_ptr<ScanSource> open_input_sequence(const std::filesystem::path& path,
                                                const SequenceInputArgs& args);

}  // namespace sarmap::cli
