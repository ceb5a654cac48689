// The Microsoft 7-Scenes layout: frame-NNNNNN.depth.png (16-bit, millimetres,
// 0 and 65535 mean no measurement) beside frame-NNNNNN.pose.txt (4x4
// camera-to-world matrix as text), frames in the order of their numbers.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string_view>

#include "engine/io/scan_source.hpp"

namespace sarmap {

inline constexpr double kSevenScenesDepthUnitsPerMetre = 1000.0;
// 7-Scenes ships no timestamps; frames come from a Kinect at 30 Hz.
inline constexpr double kSevenScenesFrameRate = 30.0;

// The frame number of "frame-000123.depth.png", or nullopt for any other name.
std::optional<unsigned long> seven_scenes_frame_number(std::string_view filename);

// Intrinsics: options.intrinsics_file, else camera-intrinsics.txt in the folder.
// Every frame's pose file must exist; poses are parsed as frames are read.
std::unique_ptr<ScanSource> open_seven_scenes_sequence(const std::filesystem::path& folder,
                                                       const ScanSequenceOptions& options);

}  // namespace sarmap
