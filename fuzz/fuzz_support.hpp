// What the fuzz targets share: a scratch folder of their own for parsers that
// read only from a path, writing the fuzzer's bytes into it, and splitting
// one input into the several files a folder layout needs.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace sarmap::fuzz {

// /dev/shm/sarmap-fuzz-PID (or the temporary folder when there is no
// /dev/shm): per process, so parallel fuzzers never share files; removed when
// the process exits normally (a crash leaves it for the reproducer's sake).
class ScratchFolder {
 public:
  ScratchFolder() {
    std::error_code ec;
    const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", ec)
                                           ? std::filesystem::path("/dev/shm")
                                           : std::filesystem::temp_directory_path();
    path_ = base / ("sarmap-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path_);
  }
  ~ScratchFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline const std::filesystem::path& scratch() {
  static const ScratchFolder folder;
  return folder.path();
}

// Replaces `path` with exactly these bytes; a failure here is the machine's,
// not the parser's, so it stops the run loudly.
inline void write_file(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// The input cut at every kPartSeparator line into at most `parts` pieces
// (missing ones empty): how one fuzz input carries a folder's several files.
inline constexpr std::string_view kPartSeparator = "\n=====\n";

inline std::vector<std::string_view> split_parts(std::string_view text, std::size_t parts) {
  std::vector<std::string_view> out;
  while (out.size() + 1 < parts) {
    const std::size_t at = text.find(kPartSeparator);
    if (at == std::string_view::npos) break;
    out.push_back(text.substr(0, at));
    text.remove_prefix(at + kPartSeparator.size());
  }
  out.push_back(text);
  out.resize(parts);
  return out;
}

// Writes `bytes` to folder/name, or removes that file when `present` is false
// (so a part the input leaves out is really absent, not left from before).
inline void place_file(const std::filesystem::path& folder, const char* name, std::string_view bytes,
                       bool present = true) {
  if (present) {
    write_file(folder / name, bytes);
  } else {
    std::error_code ec;
    std::filesystem::remove(folder / name, ec);
  }
}

// Called with every sarmap::Error a target catches (the expected outcome of a
// malformed input). Silent while fuzzing; SARMAP_FUZZ_VERBOSE=1 prints the
// message, to check that a seed parses or to read what a reproducer hits.
inline void refused(const std::exception& error) {
  static const bool verbose = std::getenv("SARMAP_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "refused: %s\n", error.what());
}

}  // namespace sarmap::fuzz
