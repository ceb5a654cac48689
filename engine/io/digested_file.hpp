// Files sarmap writes for itself and reads back whole (checkpoints, saved
// Mappers): a magic word, the body, then 64 hex digits of the SHA-256 of
// everything before them, so a damaged or truncated file is refused before
// any of it is parsed.
#pragma once

#include <filesystem>
#include <string_view>

#include "engine/io/file_bytes.hpp"

namespace sarmap {

inline constexpr std::size_t kDigestChars = 64;

// Writes `bytes` (which start with the magic word) and their digest,
// atomically: a crash leaves the previous file or none.
void write_digested_file(const std::filesystem::path& file, std::string_view bytes);

// The file's bytes after checking its magic word and digest; body() drops
// the digest. Throws sarmap::Error naming the file: Io when it cannot be
// read, Parse ("not a sarmap WHAT", "the WHAT is damaged") otherwise. These
// files are as large as the state they hold: the input size limits do not
// apply.
FileBytes read_digested_file(const std::filesystem::path& file, std::string_view magic, std::string_view what);

// The bytes before the digest of a file read_digested_file accepted.
inline std::string_view digested_body(const FileBytes& bytes) {
  return bytes.view().substr(0, bytes.size() - kDigestChars);
}

}  // namespace sarmap
