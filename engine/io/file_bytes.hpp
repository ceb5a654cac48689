// A whole file read into one buffer, so readers parse from memory (no
// per-value stream calls) and can check every size against the real length.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

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

// Throws sarmap::Error (Io) naming the path when it cannot be opened or read.
FileBytes read_file_bytes(const std::filesystem::path& path);

// Empty when `path` names a regular file; otherwise why not, to follow the
// path in an error message: " does not exist", or ": " and the system's
// reason for a name it refuses (a part longer than NAME_MAX, ...), which
// std::filesystem::is_regular_file(path) would throw as a filesystem_error.
std::string why_not_a_regular_file(const std::filesystem::path& path);

}  // namespace sarmap
