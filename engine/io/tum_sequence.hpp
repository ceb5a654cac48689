// The TUM RGB-D layout: depth.txt ("timestamp filename" per line),
// groundtruth.txt ("timestamp tx ty tz qx qy qz qw"), 16-bit depth PNGs with
// 5000 units per metre. Each depth frame takes the ground-truth pose nearest
// in time; frames with none within the tolerance are skipped and counted.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "engine/io/scan_source.hpp"

namespace sarmap {

inline constexpr double kTumDepthUnitsPerMetre = 5000.0;

// For each query time, the index of the nearest time in `sorted_references`
// (ascending; ties go to the earlier one), or nullopt when that one is
// farther than `tolerance`. O((n + m) log m).
std::vector<std::optional<std::size_t>> associate_nearest(std::span<const double> queries,
                                                          std::span<const double> sorted_references,
                                                          double tolerance);

// Intrinsics: options.intrinsics_file, else intrinsics.json in the folder.
std::unique_ptr<ScanSource> open_tum_sequence(const std::filesystem::path& folder,
                                              const ScanSequenceOptions& options);

}  // namespace sarmap
