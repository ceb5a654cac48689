// SHA-256 (FIPS 180-4) of bytes and of files: manifest.json records each
// output's hash so that a reader can tell a whole output set from a mixed or
// half-written one (docs/formats.md, "manifest.json").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace sarmap {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  void update(std::string_view text) { update(text.data(), text.size()); }
  // The digest as 64 lowercase hex digits; the hasher must not be updated after.
  std::string hex_digest();

 private:
  void compress(const std::uint8_t* block);

  std::array<std::uint32_t, 8> state_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t total_bytes_ = 0;
};

std::string sha256_hex(std::string_view bytes);

// Whether `text` is a digest as hex_digest() writes it: 64 lowercase hex digits.
bool is_sha256_hex(std::string_view text);

struct FileDigest {
  std::uint64_t bytes = 0;
  std::string sha256;
};

// Reads the file in chunks. Throws sarmap::Error (Io) naming the file when it cannot be read.
FileDigest digest_file(const std::filesystem::path& path);

}  // namespace sarmap
