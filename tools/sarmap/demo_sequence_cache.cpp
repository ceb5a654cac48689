#include "tools/sarmap/demo_sequence_cache.hpp"

#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <variant>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/core/version.hpp"
#include "engine/io/atomic_file.hpp"

namespace sarmap::cli {

namespace fs = std::filesystem;

std::uint64_t fnv1a_file(const fs::path& path, std::uint64_t hash) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::Io, path.string() + ": cannot be read");
  std::array<char, 1 << 16> buffer;
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    for (std::size_t i = 0; i < n; ++i) {
      hash ^= static_cast<unsigned char>(buffer[i]);
      hash *= 0x100000001b3ULL;
    }
  }
  if (in.bad()) throw Error(ErrorCode::Io, path.string() + ": read failed");
  return hash;
}

std::string sequence_stamp(const fs::path& arena_file, const sim::Arena& arena, std::uint64_t seed) {
  std::uint64_t hash = fnv1a_file(arena_file);
  // A mesh element's file shapes the arena as much as the JSON does.
  for (const sim::ArenaElement& element : arena.elements) {
    if (const auto* mesh = std::get_if<sim::MeshSpec>(&element.shape)) hash = fnv1a_file(mesh->path, hash);
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  nlohmann::ordered_json j;
  j["arena_fnv1a64"] = hex;
  // A sequence cached before sequences recorded their arena has a stamp
  // without this key: it is simulated again, so eval can check its runs.
  j["arena_sha256"] = arena.sha256;
  j["seed"] = seed;
  j["sarmap_version"] = kVersion;
  return j.dump() + "\n";
}

bool cached_sequence_matches(const fs::path& sequence_dir, const fs::path& stamp_file,
                             const std::string& stamp) {
  std::error_code ec;
  if (!fs::is_regular_file(sequence_dir / "sequence.json", ec)) return false;
  std::ifstream in(stamp_file, std::ios::binary);
  if (!in) return false;
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  return text == stamp;
}

void write_sequence_stamp(const fs::path& stamp_file, const std::string& stamp) {
  AtomicFileWriter writer(stamp_file);
  writer.write(stamp);
  writer.commit();
}

}  // namespace sarmap::cli
