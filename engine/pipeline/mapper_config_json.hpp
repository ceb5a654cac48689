// MapperConfig as JSON: the one config schema of a run, shared by
// `sarmap run --config`, manifest.json's "config" member and library front
// ends. Every setting of every stage has one key (its name in the settings
// structs, nested by stage) and one default (the structs' own); a file gives
// only the keys it changes. Unknown keys and values of the wrong type are
// errors naming the dotted key; ranges are checked by the stages themselves
// when a Mapper is built from the config.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/pipeline/mapper.hpp"

namespace sarmap::pipeline {

inline constexpr int kConfigVersion = 1;

// Every key, with "version" first. The dgcnn model path is written as it is
// held (absolute if the config was read from a file).
nlohmann::ordered_json config_to_json(const MapperConfig& config);

// `base` with the keys `json` gives replaced. `source` names the config in
// errors (a file name, or "config"). Throws sarmap::Error (InvalidData)
// naming the dotted key for an unknown key, a value of the wrong type, or a
// "version" other than kConfigVersion (absent is taken as the current one).
MapperConfig config_from_json(const nlohmann::ordered_json& json, const MapperConfig& base = {},
                              const std::string& source = "config");

// A config file, or a run's manifest.json (its "config" member), over `base`
// (the keys the file leaves out keep its values). A relative model path is
// taken from the file's folder. Throws sarmap::Error: Io when unreadable,
// Parse when not JSON, InvalidData as above (and for a manifest without a
// "config" member).
MapperConfig read_config_file(const std::filesystem::path& path, const MapperConfig& base = {});

}  // namespace sarmap::pipeline
