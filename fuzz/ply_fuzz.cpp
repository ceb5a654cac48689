// libFuzzer target: PLY point clouds (engine/io/ply.hpp, read_ply), ASCII and
// binary. read_ply reads only from a path, so the bytes go to a scratch file.
#include <cstddef>
#include <cstdint>

#include "engine/core/error.hpp"
#include "engine/io/ply.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto path = sarmap::fuzz::scratch() / "input.ply";
  sarmap::fuzz::write_file(path, sarmap::fuzz::as_text(data, size));
  try {
    sarmap::PointCloudFileInfo info;
    const sarmap::PointBuffer points = sarmap::read_ply(path, &info);
    (void)points;
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A malformed file refused with a message: the expected outcome.
  }
  return 0;
}
