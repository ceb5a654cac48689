#include "engine/io/atomic_file.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <random>
#include <unistd.h>

#include "engine/core/error.hpp"

namespace sarmap {
namespace {

std::string describe_errno(const std::filesystem::path& path, std::string_view action) {
  return path.string() + ": cannot " + std::string(action) + ": " + std::strerror(errno);
}

}  // namespace

AtomicFileWriter::AtomicFileWriter(std::filesystem::path target) : target_(std::move(target)) {
  std::random_device entropy;
  std::string name = ".";
  name += target_.filename().string();
  name += ".tmp.";
  name += std::to_string(::getpid());
  name += ".";
  name += std::to_string(entropy());
  const std::filesystem::path folder = target_.has_parent_path() ? target_.parent_path() : ".";
  temporary_ = folder / name;
  file_ = std::fopen(temporary_.c_str(), "wb");
  if (file_ == nullptr) throw Error(ErrorCode::Io, describe_errno(temporary_, "create temporary file"));
}

AtomicFileWriter::~AtomicFileWriter() {
  if (file_ != nullptr) std::fclose(file_);
  if (!committed_) {
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
}

void AtomicFileWriter::write(const void* data, std::size_t size) {
  if (size == 0) return;
  if (std::fwrite(data, 1, size, file_) != size) throw Error(ErrorCode::Io, describe_errno(temporary_, "write"));
}

void AtomicFileWriter::commit() {
  if (std::fflush(file_) != 0) throw Error(ErrorCode::Io, describe_errno(temporary_, "flush"));
  if (::fsync(::fileno(file_)) != 0) throw Error(ErrorCode::Io, describe_errno(temporary_, "fsync"));
  const int closed = std::fclose(file_);
  file_ = nullptr;
  if (closed != 0) throw Error(ErrorCode::Io, describe_errno(temporary_, "close"));
  if (std::rename(temporary_.c_str(), target_.c_str()) != 0) {
    throw Error(ErrorCode::Io, describe_errno(target_, "rename temporary file onto"));
  }
  committed_ = true;
}

}  // namespace sarmap
