// Parsing and writing the "sarmap.*" model metadata (see dgcnn_metadata.hpp).
#include "engine/semantic/dgcnn/dgcnn_metadata.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "engine/core/error.hpp"

namespace sarmap {
namespace {

[[noreturn]] void bad(const std::string& source, const std::string& key, const std::string& value,
                      const std::string& expected) {
  throw Error(ErrorCode::InvalidData,
              source + ": metadata '" + key + "' = \"" + value + "\": expected " + expected);
}

std::size_t parse_count(const std::string& source, const std::string& key, const std::string& value,
                        std::size_t lo, std::size_t hi) {
  std::size_t n = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
  if (ec != std::errc() || end != value.data() + value.size() || n < lo || n > hi) {
    bad(source, key, value, "an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
  }
  return n;
}

double parse_real(const std::string& source, const std::string& key, const std::string& value) {
  std::istringstream in(value);
  in.imbue(std::locale::classic());
  double v = 0.0;
  if (!(in >> v) || !(in >> std::ws).eof() || !std::isfinite(v)) bad(source, key, value, "a finite number");
  return v;
}

std::string format_real(double v) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out.precision(17);
  out << v;
  return out.str();
}

}  // namespace

DgcnnMetadata parse_dgcnn_metadata(const std::map<std::string, std::string>& entries, const std::string& source) {
  DgcnnMetadata m;
  auto get = [&](const char* key) -> const std::string* {
    const auto it = entries.find(key);
    return it == entries.end() ? nullptr : &it->second;
  };
  if (const auto* v = get("sarmap.k")) m.k = parse_count(source, "sarmap.k", *v, 1, 64);
  if (const auto* v = get("sarmap.points_per_block")) {
    m.points_per_block = parse_count(source, "sarmap.points_per_block", *v, 1, kMaxPointsPerBlock);
  }
  if (const auto* v = get("sarmap.block_size")) {
    m.block_size = parse_real(source, "sarmap.block_size", *v);
    if (m.block_size <= 0.0) bad(source, "sarmap.block_size", *v, "a positive size in metres");
  }
  if (const auto* v = get("sarmap.z_min")) m.z_min = parse_real(source, "sarmap.z_min", *v);
  if (const auto* v = get("sarmap.z_max")) m.z_max = parse_real(source, "sarmap.z_max", *v);
  if (m.z_max <= m.z_min) bad(source, "sarmap.z_max", format_real(m.z_max), "a value above sarmap.z_min");
  if (const auto* v = get("sarmap.normalisation")) {
    if (*v != kCellXyFixedZ) bad(source, "sarmap.normalisation", *v, std::string("\"") + kCellXyFixedZ + "\"");
    m.normalisation = *v;
  }
  if (const auto* v = get("sarmap.classes")) {
    std::size_t start = 0;
    while (start <= v->size()) {
      const std::size_t comma = std::min(v->find(',', start), v->size());
      const std::string name = v->substr(start, comma - start);
      const auto id = class_from_name(name);
      if (!id) bad(source, "sarmap.classes", *v, "comma-separated class names (\"" + name + "\" is not one)");
      if (std::find(m.classes.begin(), m.classes.end(), *id) != m.classes.end()) {
        bad(source, "sarmap.classes", *v, "distinct class names (\"" + name + "\" repeats)");
      }
      m.classes.push_back(*id);
      start = comma + 1;
    }
  }
  return m;
}

std::map<std::string, std::string> dgcnn_metadata_entries(const DgcnnMetadata& m) {
  std::map<std::string, std::string> out{
      {"sarmap.k", std::to_string(m.k)},
      {"sarmap.points_per_block", std::to_string(m.points_per_block)},
      {"sarmap.block_size", format_real(m.block_size)},
      {"sarmap.z_min", format_real(m.z_min)},
      {"sarmap.z_max", format_real(m.z_max)},
  };
  if (!m.normalisation.empty()) out["sarmap.normalisation"] = m.normalisation;
  if (!m.classes.empty()) {
    std::string names;
    for (ClassId c : m.classes) names += (names.empty() ? "" : ",") + std::string(class_info(c).name);
    out["sarmap.classes"] = names;
  }
  return out;
}

}  // namespace sarmap
