// libFuzzer target: the TUM RGB-D folder's text files
// (engine/io/tum_sequence.hpp, with engine/io/sequence_text.hpp and
// intrinsics.hpp underneath): one input holds depth.txt, groundtruth.txt and
// intrinsics.json (JSON or a 3x3 text matrix), cut at "\n=====\n" lines; an
// empty last part leaves intrinsics.json out. The folder is opened as a scan
// source and its first frames read; it also holds d.png, a valid 4 x 3 depth
// image the list can name.
#include <cstddef>
#include <cstdint>

#include "engine/core/error.hpp"
#include "engine/core/scan.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/io/tum_sequence.hpp"
#include "fuzz/depth_frame.hpp"
#include "fuzz/fuzz_support.hpp"

namespace {

const std::filesystem::path& tum_folder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path dir = sarmap::fuzz::scratch() / "tum";
    std::filesystem::create_directories(dir);
    sarmap::fuzz::write_file(dir / "d.png", sarmap::fuzz::depth_frame_png());
    return dir;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto parts = sarmap::fuzz::split_parts(sarmap::fuzz::as_text(data, size), 3);
  const std::filesystem::path& dir = tum_folder();
  sarmap::fuzz::place_file(dir, "depth.txt", parts[0]);
  sarmap::fuzz::place_file(dir, "groundtruth.txt", parts[1]);
  sarmap::fuzz::place_file(dir, "intrinsics.json", parts[2], !parts[2].empty());
  try {
    const auto source = sarmap::open_tum_sequence(dir, sarmap::ScanSequenceOptions{});
    sarmap::Scan scan;
    for (int i = 0; i < 4 && source->next(scan); ++i) {
    }
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A malformed file refused with a message: the expected outcome.
  }
  return 0;
}
