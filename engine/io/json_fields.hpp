// Strict reading of the JSON files sarmap writes for itself (segments.json,
// graph.json): a missing key or a value of the wrong type is an error naming
// the file, the entry and the key, never a default taken in silence.
#pragma once

#include <filesystem>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace sarmap::json_fields {

using Json = nlohmann::ordered_json;

// The parsed file. Throws sarmap::Error: Io when it cannot be read, Parse when it is not JSON.
Json read_file(const std::filesystem::path& path);

// Throws sarmap::Error (InvalidData): "<file>: <where>: <what>".
[[noreturn]] void fail(const std::filesystem::path& path, const std::string& where, const std::string& what);

// The member `key` of the object `j`; fails naming the key when absent.
const Json& member(const Json& j, const char* key, const std::filesystem::path& path, const std::string& where);
double number(const Json& j, const char* key, const std::filesystem::path& path, const std::string& where);
// A value that must be three numbers; `name` is the key it came from.
Eigen::Vector3d vector3(const Json& value, const std::string& name, const std::filesystem::path& path,
                        const std::string& where);

}  // namespace sarmap::json_fields
