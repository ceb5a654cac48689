// libFuzzer target: the 7-Scenes folder's text files
// (engine/io/seven_scenes_sequence.hpp, with engine/io/sequence_text.hpp and
// intrinsics.hpp underneath): one input holds camera-intrinsics.txt (a 3x3
// matrix, or JSON) and frame-000000.pose.txt (a 4x4 matrix), cut at a
// "\n=====\n" line. The folder also holds frame-000000.depth.png, a valid 4 x 3
// depth image; it is opened as a scan source and its frame read.
#include <cstddef>
#include <cstdint>

#include "engine/core/error.hpp"
#include "engine/core/scan.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/io/seven_scenes_sequence.hpp"
#include "fuzz/depth_frame.hpp"
#include "fuzz/fuzz_support.hpp"

namespace {

const std::filesystem::path& scenes_folder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path dir = sarmap::fuzz::scratch() / "7scenes";
    std::filesystem::create_directories(dir);
    sarmap::fuzz::write_file(dir / "frame-000000.depth.png", sarmap::fuzz::depth_frame_png());
    return dir;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto parts = sarmap::fuzz::split_parts(sarmap::fuzz::as_text(data, size), 2);
  const std::filesystem::path& dir = scenes_folder();
  sarmap::fuzz::place_file(dir, "camera-intrinsics.txt", parts[0]);
  sarmap::fuzz::place_file(dir, "frame-000000.pose.txt", parts[1]);
  try {
    const auto source = sarmap::open_seven_scenes_sequence(dir, sarmap::ScanSequenceOptions{});
    sarmap::Scan scan;
    while (source->next(scan)) {
    }
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A malformed file refused with a message: the expected outcome.
  }
  return 0;
}
