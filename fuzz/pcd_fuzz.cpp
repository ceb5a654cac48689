// libFuzzer target: PCD point clouds (engine/io/pcd.hpp, read_pcd): ascii,
// binary and binary_compressed (LZF). read_pcd reads only from a path, so the
// bytes go to a scratch file.
#include <cstddef>
#include <cstdint>

#include "engine/core/error.hpp"
#include "engine/io/pcd.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto path = sarmap::fuzz::scratch() / "input.pcd";
  sarmap::fuzz::write_file(path, sarmap::fuzz::as_text(data, size));
  try {
    sarmap::PointCloudFileInfo info;
    const sarmap::PointBuffer points = sarmap::read_pcd(path, &info);
    (void)points;
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A malformed file refused with a message: the expected outcome.
  }
  return 0;
}
