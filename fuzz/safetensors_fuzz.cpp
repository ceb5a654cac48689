// libFuzzer target: safetensors files (engine/io/safetensors.hpp,
// SafetensorsFile::parse from memory): the JSON header, every tensor's dtype,
// shape and byte range, the metadata, and the float32 values of each F32
// tensor.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/safetensors.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const sarmap::SafetensorsFile file =
        sarmap::SafetensorsFile::parse(std::vector<std::uint8_t>(data, data + size), "fuzz.safetensors");
    for (const sarmap::SafetensorsTensor& tensor : file.tensors()) {
      if (file.find(tensor.name) != &tensor) __builtin_trap();  // find() must return the listed tensor
      if (tensor.dtype == "F32") (void)file.floats(tensor);
    }
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A malformed file refused with a message: the expected outcome.
  }
  return 0;
}
