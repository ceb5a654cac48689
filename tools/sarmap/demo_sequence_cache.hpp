// The demo's simulated sequence is cached between runs: a stamp file beside it
// records what made it (the arena file's bytes and its meshes', the noise
// seed, the sarmap version), and a matching stamp lets the demo skip simulation.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "engine/sim/arena.hpp"

namespace sarmap::cli {

// 64-bit FNV-1a of a file's bytes, folded into `hash`. Throws sarmap::Error(Io)
// when the file cannot be read.
std::uint64_t fnv1a_file(const std::filesystem::path& path, std::uint64_t hash = 0xcbf29ce484222325ULL);

// One line of JSON naming everything the simulated sequence depends on.
std::string sequence_stamp(const std::filesystem::path& arena_file, const sim::Arena& arena,
                           std::uint64_t seed);

// True when `sequence_dir` holds a finished sequence (sequence.json) and
// `stamp_file` holds exactly `stamp`.
bool cached_sequence_matches(const std::filesystem::path& sequence_dir,
                             const std::filesystem::path& stamp_file, const std::string& stamp);

// Written atomically, after the sequence is complete.
void write_sequence_stamp(const std::filesystem::path& stamp_file, const std::string& stamp);

}  // namespace sarmap::cli
