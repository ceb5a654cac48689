// libFuzzer target: sarmap's metric-map file, map.sarmap
// (engine/metric/map_file.hpp, load_map). The input is the file without its
// trailing CRC-32: the target appends the right checksum, so mutations reach
// the header, block and voxel checks behind it instead of all stopping at a
// checksum mismatch. load_map takes only a path, so the bytes go to a scratch
// file.
#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/error.hpp"
#include "engine/metric/map_file.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto path = sarmap::fuzz::scratch() / "map.sarmap";
  std::string bytes(sarmap::fuzz::as_text(data, size));
  const auto crc = static_cast<std::uint32_t>(crc32(crc32(0L, Z_NULL, 0), data, static_cast<uInt>(size)));
  for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((crc >> (8 * i)) & 0xff));
  sarmap::fuzz::write_file(path, bytes);
  try {
    const sarmap::metric::MetricMap map = sarmap::metric::load_map(path);
    (void)map;
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A malformed file refused with a message: the expected outcome.
  }
  return 0;
}
