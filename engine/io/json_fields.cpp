#include "engine/io/json_fields.hpp"

#include <fstream>
#include <sstream>

#include "engine/core/error.hpp"
#include "engine/io/file_bytes.hpp"

namespace sarmap::json_fields {

Json read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::Io, path.string() + ": cannot open");
  check_input_file_size(path);
  std::stringstream text;
  text << in.rdbuf();
  Json j = Json::parse(text.str(), nullptr, false);
  if (j.is_discarded()) throw Error(ErrorCode::Parse, path.string() + ": not valid JSON");
  return j;
}

void fail(const std::filesystem::path& path, const std::string& where, const std::string& what) {
  throw Error(ErrorCode::InvalidData, path.string() + ": " + where + ": " + what);
}

const Json& member(const Json& j, const char* key, const std::filesystem::path& path, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) fail(path, where, std::string("missing \"") + key + "\"");
  return j[key];
}

double number(const Json& j, const char* key, const std::filesystem::path& path, const std::string& where) {
  const Json& v = member(j, key, path, where);
  if (!v.is_number()) fail(path, where, std::string("\"") + key + "\" is not a number");
  return v.get<double>();
}

Eigen::Vector3d vector3(const Json& v, const std::string& name, const std::filesystem::path& path,
                        const std::string& where) {
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number()) {
    fail(path, where, "\"" + name + "\" is not three numbers");
  }
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

}  // namespace sarmap::json_fields
