// Recognises which layout a path holds and opens the matching reader.
#include "engine/io/scan_source.hpp"

#include <system_error>

#include "engine/core/error.hpp"
#include "engine/io/sarmap_sequence.hpp"
#include "engine/io/seven_scenes_sequence.hpp"
#include "engine/io/single_cloud_source.hpp"
#include "engine/io/tum_sequence.hpp"

namespace sarmap {
namespace {

bool has_seven_scenes_frame(const std::filesystem::path& folder) {
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (seven_scenes_frame_number(entry.path().filename().string())) return true;
  }
  return false;
}

}  // namespace

std::unique_ptr<ScanSource> open_scan_sequence(const std::filesystem::path& path,
                                               const ScanSequenceOptions& options) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) {
    throw Error(ErrorCode::Io, path.string() + ": no such file or folder");
  }
  if (std::filesystem::is_regular_file(status)) {
    if (path.filename() == "sequence.json") {
      return open_sarmap_sequence(path.has_parent_path() ? path.parent_path() : ".", options.limits);
    }
    return open_single_cloud(path, options.limits);
  }
  if (!std::filesystem::is_directory(status)) {
    throw Error(ErrorCode::Io, path.string() + ": neither a file nor a folder");
  }
  if (std::filesystem::exists(path / "sequence.json")) return open_sarmap_sequence(path, options.limits);
  if (std::filesystem::exists(path / "depth.txt")) return open_tum_sequence(path, options);
  if (has_seven_scenes_frame(path)) return open_seven_scenes_sequence(path, options);
  throw Error(ErrorCode::InvalidArgument,
              path.string() +
                  ": not a recognised scan sequence: expected sequence.json (sarmap), "
                  "depth.txt + groundtruth.txt (TUM RGB-D) or frame-NNNNNN.depth.png + "
                  "frame-NNNNNN.pose.txt (7-Scenes)");
}

}  // namespace sarmap
