// Whole-file reads and writes for the tests that inspect, cut or corrupt the
// files the engine writes.
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace sarmap::test {

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Replaces the file with `bytes`. A fresh file each time: ext4 flushes to
// disk when a file is truncated and rewritten, which would make the tests
// that corrupt a file byte by byte take seconds.
inline void spit(const std::filesystem::path& path, const std::string& bytes) {
  std::filesystem::remove(path);
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

}  // namespace sarmap::test
