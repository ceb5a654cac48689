// libFuzzer target: 16-bit grayscale PNG depth images (engine/io/depth_image.hpp,
// read_depth_png), the frames of TUM RGB-D and 7-Scenes folders. The reader
// takes only a path, so the bytes go to a scratch file.
#include <cstddef>
#include <cstdint>

#include "engine/core/error.hpp"
#include "engine/io/depth_image.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto path = sarmap::fuzz::scratch() / "input.png";
  sarmap::fuzz::write_file(path, sarmap::fuzz::as_text(data, size));
  try {
    const sarmap::DepthImage image = sarmap::read_depth_png(path);
    (void)image;
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A malformed file refused with a message: the expected outcome.
  }
  return 0;
}
