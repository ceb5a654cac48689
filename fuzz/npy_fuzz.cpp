// libFuzzer target: numpy .npy float32 arrays (engine/io/npy.hpp,
// read_npy_f32), the prepared DGCNN blocks. The reader takes only a path, so
// the bytes go to a scratch file.
#include <cstddef>
#include <cstdint>

#include "engine/core/error.hpp"
#include "engine/io/npy.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto path = sarmap::fuzz::scratch() / "input.npy";
  sarmap::fuzz::write_file(path, sarmap::fuzz::as_text(data, size));
  try {
    const sarmap::NpyArray array = sarmap::read_npy_f32(path);
    (void)array;
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A malformed file refused with a message: the expected outcome.
  }
  return 0;
}
