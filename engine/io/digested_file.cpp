#include "engine/io/digested_file.hpp"

#include <cstdint>
#include <limits>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/sha256.hpp"

namespace sarmap {

void write_digested_file(const std::filesystem::path& file, std::string_view bytes) {
  AtomicFileWriter writer(file);
  writer.write(bytes);
  writer.write(sha256_hex(bytes));
  writer.commit();
}

FileBytes read_digested_file(const std::filesystem::path& file, std::string_view magic, std::string_view what) {
  FileBytes file_bytes = read_file_bytes(file, std::numeric_limits<std::uint64_t>::max());
  const std::string_view bytes = file_bytes.view();
  if (bytes.size() < magic.size() + kDigestChars || bytes.substr(0, magic.size()) != magic) {
    throw Error(ErrorCode::Parse, file.string() + ": not a sarmap " + std::string(what));
  }
  const std::string_view stored = bytes.substr(bytes.size() - kDigestChars);
  if (sha256_hex(bytes.substr(0, bytes.size() - kDigestChars)) != stored) {
    throw Error(ErrorCode::Parse,
                file.string() + ": the " + std::string(what) + " is damaged (its SHA-256 does not match)");
  }
  return file_bytes;
}

}  // namespace sarmap
