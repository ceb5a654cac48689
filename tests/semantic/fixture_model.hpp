// The small fixture network (tests/data/dgcnn/model_c6) for the tests that
// run it over whole scans or maps: they check when blocks run and how their
// scores travel, not the network's figures.
//
// In the release build it is the file itself. Under the sanitizers it is a
// copy whose metadata asks for 1,024 points per block instead of 4,096 (the
// same weights), written once per test process and removed at its exit: the
// sanitizers check every vector load of the kNN and EdgeConv kernels, which
// makes a 4,096-point block cost about fifty times its release time and made
// these tests most of CI's sanitizer time (docs/reliability.md, "CI's time"). The
// kernels' own tests still run every block size there, and the golden tests
// keep the original file.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "tests/release_only.hpp"

namespace sarmap::test {

namespace fixture_model_detail {

// The copy: `original` with its header's points per block 4096 -> 1024 (same
// length, so the header's size and the tensors' offsets stay).
inline std::filesystem::path write_small_block_copy(const std::filesystem::path& original) {
  std::ifstream in(original, std::ios::binary);
  std::string bytes{std::istreambuf_iterator<char>(in), {}};
  std::uint64_t header_size = 0;
  if (bytes.size() < 8) throw std::runtime_error("fixture model too short: " + original.string());
  std::memcpy(&header_size, bytes.data(), 8);
  const std::size_t header_end = 8 + header_size;
  const std::size_t key = bytes.find("\"sarmap.points_per_block\"", 8);
  const std::size_t value = key == std::string::npos ? key : bytes.find("\"4096\"", key);
  if (value == std::string::npos || value >= header_end) {
    throw std::runtime_error("fixture model's header has no points_per_block 4096: " + original.string());
  }
  bytes.replace(value, 6, "\"1024\"");
  const std::filesystem::path copy = std::filesystem::temp_directory_path() /
                                     ("sarmap-test-model-c6-n1024-" + std::to_string(::getpid()) + ".safetensors");
  std::ofstream(copy, std::ios::binary | std::ios::trunc) << bytes;
  return copy;
}

struct RemovedAtExit {
  std::filesystem::path path;
  ~RemovedAtExit() {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
  }
};

}  // namespace fixture_model_detail

inline std::filesystem::path fixture_model_c6() {
  const std::filesystem::path original = SARMAP_TEST_DATA_DIR "/dgcnn/model_c6.safetensors";
  if (!kSanitizedBuild) return original;
  static const fixture_model_detail::RemovedAtExit copy{fixture_model_detail::write_small_block_copy(original)};
  return copy.path;
}

}  // namespace sarmap::test
