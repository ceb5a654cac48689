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

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "engine/io/safetensors.hpp"
#include "tests/release_only.hpp"

namespace sarmap::test {

namespace fixture_model_detail {

// The copy: `original`'s float tensors and metadata, with 1,024 points per
// block. The int64 batch-norm counters are left out: loading ignores them.
inline void write_small_block_copy(const std::filesystem::path& original, const std::filesystem::path& copy) {
  const SafetensorsFile file = SafetensorsFile::read(original);
  std::vector<std::vector<float>> values;
  values.reserve(file.tensors().size());  // the tensors below point into it
  std::vector<SafetensorsFloatTensor> tensors;
  for (const SafetensorsTensor& tensor : file.tensors()) {
    if (tensor.dtype != "F32") continue;
    values.push_back(file.floats(tensor));
    tensors.push_back({tensor.name, tensor.shape, values.back()});
  }
  auto metadata = file.metadata();
  metadata.at("sarmap.points_per_block") = "1024";
  write_safetensors(copy, tensors, metadata);
}

// The copy's file, of this test process alone (the pid in its name),
// removed at exit.
class SmallBlockCopy {
 public:
  explicit SmallBlockCopy(const std::filesystem::path& original)
      : path_(std::filesystem::temp_directory_path() /
              ("sarmap-test-model-c6-n1024-" + std::to_string(::getpid()) + ".safetensors")) {
    write_small_block_copy(original, path_);
  }
  SmallBlockCopy(const SmallBlockCopy&) = delete;
  SmallBlockCopy& operator=(const SmallBlockCopy&) = delete;
  ~SmallBlockCopy() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace fixture_model_detail

inline std::filesystem::path fixture_model_c6() {
  const std::filesystem::path original = SARMAP_TEST_DATA_DIR "/dgcnn/model_c6.safetensors";
  if (!kSanitizedBuild) return original;
  static const fixture_model_detail::SmallBlockCopy copy(original);
  return copy.path();
}

}  // namespace sarmap::test
