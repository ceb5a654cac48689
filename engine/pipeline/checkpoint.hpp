// A run's checkpoint: the Mapper's whole state between two scans and where
// the run stood in its input, in one file written atomically, so that a run
// killed at any moment can continue from its last checkpoint and end with
// the outputs an uninterrupted run writes (docs/reliability.md, "Resume").
//
// Layout (native byte order; a checkpoint resumes on the machine that wrote
// it): "SARMAPCK" | u32 version | the header's fields | Mapper::save_state
// | 64 hex digits: SHA-256 of every byte before them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "engine/pipeline/mapper.hpp"

namespace sarmap::pipeline {

inline constexpr std::uint32_t kCheckpointVersion = 6;

struct CheckpointHeader {
  // What the run was started with (settings, input and model hashes): a
  // resume with another fingerprint would mix two runs' maps.
  std::string fingerprint;
  std::uint64_t next_frame = 0;  // the input frame to read next
  std::uint64_t scans = 0;       // scans integrated so far (skipped ones not counted)
  double elapsed_s = 0;          // wall time the run has taken so far
};

// Written atomically: a crash leaves the previous checkpoint or none.
void save_checkpoint(const std::filesystem::path& file, const CheckpointHeader& header, const Mapper& mapper);

// Loads the state into `mapper` (made with the run's config) after checking
// that the file's fingerprint is `fingerprint`; returns the header. Throws
// sarmap::Error naming the file: InvalidArgument when the fingerprints differ
// (another config or input), Io when it cannot be read, Parse when it is
// damaged or from another checkpoint version.
CheckpointHeader load_checkpoint(const std::filesystem::path& file, const std::string& fingerprint, Mapper& mapper);

}  // namespace sarmap::pipeline
