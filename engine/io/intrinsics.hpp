// Pinhole intrinsics of a depth camera read from a file, in either of the two
// forms datasets ship: JSON {"fx","fy","cx","cy"[, "width","height"]} or a
// 3x3 camera matrix as text ("fx 0 cx / 0 fy cy / 0 0 1").
#pragma once

#include <filesystem>
#include <optional>
#include <string_view>

#include "engine/core/sensor_info.hpp"

namespace sarmap {

// Chooses the form by the first non-blank character ('{' = JSON). Throws
// sarmap::Error naming the file and the field for anything unusable (a
// non-positive focal length, skew, a last row other than 0 0 1, ...).
PinholeIntrinsics read_intrinsics_file(const std::filesystem::path& path);

// Throws InvalidData unless fx, fy > 0 and everything is finite; width and
// height are 0 (unknown) or positive. `what` names the source.
void validate_intrinsics(const PinholeIntrinsics& intrinsics, std::string_view what);

// The intrinsics of a depth-image sequence: from `option_file`
// (ScanSequenceOptions::intrinsics_file) when given, else from `folder_file`
// when it exists; otherwise an InvalidArgument error that names the option
// and the file looked for, `layout` naming the dataset ("TUM RGB-D folder").
PinholeIntrinsics find_intrinsics(const std::optional<std::filesystem::path>& option_file,
                                  const std::filesystem::path& folder_file, std::string_view layout);

}  // namespace sarmap
