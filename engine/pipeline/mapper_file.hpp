// A whole Mapper in one file, to be loaded without its input: what
// `sarmap run --keep-state` leaves in a run folder (mapper.state) and
// `sarmap merge` reads. Unlike a checkpoint, which continues one run from
// the same command line, it carries what it takes to make the Mapper again:
// its config and its sensor (docs/formats.md, "mapper.state").
//
// Layout (native byte order; loads on the kind of machine that wrote it):
// "SARMAPMF" | u32 version | config JSON | sensor | Mapper::save_state
// | 64 hex digits: SHA-256 of every byte before them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>

#include "engine/pipeline/mapper.hpp"

namespace sarmap::pipeline {

inline constexpr std::uint32_t kMapperFileVersion = 2;
inline constexpr const char* kMapperFileName = "mapper.state";

// Written atomically. The Mapper is saved as it stands (finish() it first
// for a run's final maps).
void save_mapper_file(const std::filesystem::path& file, const Mapper& mapper);

// A Mapper made from the file's config and sensor, with its state. A DGCNN
// classifier loads its model from the config's path again, which must still
// hold a model of the same classes. Throws sarmap::Error naming the file:
// Io when unreadable, Parse when damaged, truncated or of another version,
// InvalidData when its config is not one this sarmap reads.
std::unique_ptr<Mapper> load_mapper_file(const std::filesystem::path& file);

// The same for a Mapper that lives elsewhere (a Python object holds its
// own): `make` builds it from the file's config and sensor and returns it;
// the state then loads into it.
using MakeMapper = std::function<Mapper&(const MapperConfig&, const SensorInfo&)>;
void load_mapper_file(const std::filesystem::path& file, const MakeMapper& make);

}  // namespace sarmap::pipeline
