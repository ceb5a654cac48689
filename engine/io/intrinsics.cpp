#include "engine/io/intrinsics.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/sequence_text.hpp"

namespace sarmap {
namespace {

double json_number(const nlohmann::json& j, const char* key, const std::string& file) {
  if (!j.contains(key)) throw Error(ErrorCode::Parse, file + ": missing key \"" + key + "\"");
  const auto& v = j.at(key);
  if (!v.is_number()) throw Error(ErrorCode::Parse, file + ": " + key + ": expected a number");
  return v.get<double>();
}

int json_dimension(const nlohmann::json& j, const char* key, const std::string& file) {
  const auto& v = j.at(key);
  if (!v.is_number_integer() || v.get<long long>() <= 0 || v.get<long long>() > 1'000'000) {
    throw Error(ErrorCode::InvalidData, file + ": " + key + ": expected a positive whole number of pixels");
  }
  return static_cast<int>(v.get<long long>());
}

PinholeIntrinsics from_json(const std::string& text, const std::string& file) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(ErrorCode::Parse, file + ": invalid JSON: " + e.what());
  }
  if (!j.is_object()) throw Error(ErrorCode::Parse, file + ": expected a JSON object");
  static const std::set<std::string> known{"fx", "fy", "cx", "cy", "width", "height"};
  for (const auto& [key, value] : j.items()) {
    if (!known.contains(key)) {
      throw Error(ErrorCode::Parse, file + ": unknown key \"" + key +
                                        "\" (expected fx, fy, cx, cy and optionally width, height)");
    }
  }
  PinholeIntrinsics k;
  k.fx = json_number(j, "fx", file);
  k.fy = json_number(j, "fy", file);
  k.cx = json_number(j, "cx", file);
  k.cy = json_number(j, "cy", file);
  if (j.contains("width") != j.contains("height")) {
    throw Error(ErrorCode::Parse, file + ": width and height must be given together");
  }
  if (j.contains("width")) {
    k.width = json_dimension(j, "width", file);
    k.height = json_dimension(j, "height", file);
  }
  return k;
}

PinholeIntrinsics from_matrix_text(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::vector<TextRow> rows = read_text_rows(path);
  if (rows.size() != 3) {
    throw Error(ErrorCode::Parse, file + ": expected a 3x3 camera matrix (3 lines of 3 numbers), got " +
                                      std::to_string(rows.size()) + " lines");
  }
  double m[3][3];
  for (int r = 0; r < 3; ++r) {
    expect_token_count(rows[r], 3, file, "one row of the 3x3 camera matrix");
    for (int c = 0; c < 3; ++c) {
      m[r][c] = parse_number(rows[r].tokens[c], file, rows[r].line,
                             "K[" + std::to_string(r) + "][" + std::to_string(c) + "]");
    }
  }
  if (m[0][1] != 0.0) {
    throw Error(ErrorCode::Unsupported,
                at_line(file, rows[0].line, "skew K[0][1] must be 0, got " + std::to_string(m[0][1])));
  }
  if (m[1][0] != 0.0 || m[2][0] != 0.0 || m[2][1] != 0.0 || m[2][2] != 1.0) {
    throw Error(ErrorCode::InvalidData,
                file + ": not a pinhole camera matrix: expected rows [fx 0 cx], [0 fy cy], [0 0 1]");
  }
  PinholeIntrinsics k;
  k.fx = m[0][0];
  k.fy = m[1][1];
  k.cx = m[0][2];
  k.cy = m[1][2];
  return k;
}

}  // namespace

void validate_intrinsics(const PinholeIntrinsics& k, std::string_view what) {
  const std::string w(what);
  if (!std::isfinite(k.fx) || !std::isfinite(k.fy) || !std::isfinite(k.cx) || !std::isfinite(k.cy)) {
    throw Error(ErrorCode::InvalidData, w + ": intrinsics must be finite numbers");
  }
  if (k.fx <= 0 || k.fy <= 0) {
    throw Error(ErrorCode::InvalidData, w + ": focal lengths fx and fy must be positive, got fx=" +
                                            std::to_string(k.fx) + " fy=" + std::to_string(k.fy));
  }
  if (k.width < 0 || k.height < 0) {
    throw Error(ErrorCode::InvalidData, w + ": image width and height must be positive");
  }
}

PinholeIntrinsics read_intrinsics_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw Error(ErrorCode::Io, path.string() + ": cannot open intrinsics file: " + std::strerror(errno));
  check_input_file_size(path);
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  std::size_t first = 0;
  while (first < text.size() && std::isspace(static_cast<unsigned char>(text[first]))) ++first;
  const PinholeIntrinsics k =
      first < text.size() && text[first] == '{' ? from_json(text, path.string()) : from_matrix_text(path);
  validate_intrinsics(k, path.string());
  return k;
}

PinholeIntrinsics find_intrinsics(const std::optional<std::filesystem::path>& option_file,
                                  const std::filesystem::path& folder_file, std::string_view layout) {
  if (option_file) return read_intrinsics_file(*option_file);
  if (std::filesystem::exists(folder_file)) return read_intrinsics_file(folder_file);
  throw Error(ErrorCode::InvalidArgument,
              folder_file.parent_path().string() + ": the " + std::string(layout) +
                  " has no camera intrinsics: pass an intrinsics file (ScanSequenceOptions::intrinsics_file, "
                  "CLI --intrinsics FILE) or put " +
                  folder_file.filename().string() + " in the folder");
}

}  // namespace sarmap
