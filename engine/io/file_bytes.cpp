#include "engine/io/file_bytes.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <sys/stat.h>
#include <system_error>
#include <unistd.h>

#include "engine/core/error.hpp"

namespace sarmap {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, std::string_view action, int error) {
  throw Error(ErrorCode::Io, path.string() + ": cannot " + std::string(action) + ": " + std::strerror(error));
}

[[noreturn]] void too_large(const std::filesystem::path& path, std::uint64_t size, std::uint64_t max_bytes) {
  throw Error(ErrorCode::OutOfRange, path.string() + ": " + std::to_string(size) + " bytes, more than the limit of " +
                                         std::to_string(max_bytes) + " bytes for one input file (sarmap's --max-file-mb)");
}

// Closes the descriptor on every path out of read_file_bytes.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

FileBytes read_file_bytes(const std::filesystem::path& path, std::uint64_t max_bytes) {
  const Descriptor file{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  if (file.fd < 0) fail(path, "open", errno);
  struct stat status {};
  if (::fstat(file.fd, &status) != 0) fail(path, "stat", errno);
  if (S_ISDIR(status.st_mode)) fail(path, "read", EISDIR);
  const auto size = static_cast<std::size_t>(status.st_size);
  if (static_cast<std::uint64_t>(status.st_size) > max_bytes) too_large(path, status.st_size, max_bytes);
  // Uninitialised on purpose: every byte is overwritten by read() below.
  auto data = std::make_unique_for_overwrite<char[]>(size == 0 ? 1 : size);
  std::size_t done = 0;
  while (done < size) {
    const ssize_t got = ::read(file.fd, data.get() + done, size - done);
    if (got < 0) {
      if (errno == EINTR) continue;
      fail(path, "read", errno);
    }
    if (got == 0) break;  // the file shrank while we read it
    done += static_cast<std::size_t>(got);
  }
  return FileBytes(std::move(data), done);
}

void check_input_file_size(const std::filesystem::path& path, std::uint64_t max_bytes) {
  struct stat status {};
  if (::stat(path.c_str(), &status) == 0 && S_ISREG(status.st_mode) &&
      static_cast<std::uint64_t>(status.st_size) > max_bytes) {
    too_large(path, static_cast<std::uint64_t>(status.st_size), max_bytes);
  }
}

std::string why_not_a_regular_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec)) return {};
  const bool refused = ec && ec != std::errc::no_such_file_or_directory;
  return refused ? ": " + ec.message() : std::string(" does not exist");
}

}  // namespace sarmap
