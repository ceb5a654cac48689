// A whole file read into one buffer, so readers parse from memory (no
// per-value stream calls) and can check every size against the real length.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "engine/io/input_limits.hpp"

namespace sarmap {

class FileBytes {
 public:
  FileBytes() = default;
  FileBytes(std::unique_ptr<char[]> data, std::size_t size) : data_(std::move(data)), size_(size) {}

  const char* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  std::string_view view() const { return {data_.get(), size_}; }

 private:
  std::unique_ptr<char[]> data_;
  std::size_t size_ = 0;
};

// Throws sarmap::Error naming the path: Io when it cannot be opened or read,
// OutOfRange when it holds more than `max_bytes` (checked before allocating).
FileBytes read_file_bytes(const std::filesystem::path& path,
                          std::uint64_t max_bytes = InputLimits{}.max_file_bytes);

// Throws sarmap::Error (OutOfRange) naming the path when the file holds
// more than `max_bytes`, for readers that stream a file whole into memory;
// a file that cannot be examined is left to the reader's own open to report.
void check_input_file_size(const std::filesystem::path& path,
                           std::uint64_t max_bytes = InputLimits{}.max_file_bytes);

// Empty when `path` names a regular file; otherwise why not, to follow the
// path in an error message: " does not exist", or ": " and the system's
// reason for a name it refuses (a part longer than NAME_MAX, ...), which
// std::filesystem::is_regular_file(path) would throw as a filesystem_error.
std::string why_not_a_regular_file(const std::filesystem::path& path);

}  // namespace sarmap
