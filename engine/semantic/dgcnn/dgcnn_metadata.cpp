// Parsing and writing the "sarmap.*" model metadata (see dgcnn_metadata.hpp).
#include "engine/semantic/dgcnn/dgcnn_metadata.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

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

// sarmap.class_map: a JSON object from the model's class names to sarmap's.
std::map<std::string, ClassId> parse_class_map(const std::string& source, const std::string& value,
                                               const std::vector<std::string>& model_classes) {
  const char* key = "sarmap.class_map";
  const nlohmann::json j = nlohmann::json::parse(value, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    bad(source, key, value, "a JSON object from the model's class names to sarmap's");
  }
  std::map<std::string, ClassId> out;
  for (const auto& [name, target] : j.items()) {
    if (std::find(model_classes.begin(), model_classes.end(), name) == model_classes.end()) {
      bad(source, key, value, "the model's class names as keys (\"" + name + "\" is not in sarmap.classes)");
    }
    const auto id = target.is_string() ? class_from_name(target.get<std::string>()) : std::nullopt;
    if (!id || *id == ClassId::Unknown) {
      bad(source, key, value,
          "sarmap classes as values (\"" + name + "\": " + target.dump() +
              " is not terrain, wall, inclined_ramp, flat_ramp or other)");
    }
    out[name] = *id;
  }
  return out;
}

}  // namespace

ClassId default_sarmap_class(const std::string& model_class) {
  if (model_class == "floor" || model_class == "ground") return ClassId::Terrain;
  const auto id = class_from_name(model_class);
  return id && *id != ClassId::Unknown ? *id : ClassId::Other;
}

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
      if (name.empty()) bad(source, "sarmap.classes", *v, "comma-separated class names (an empty one)");
      if (std::find(m.class_names.begin(), m.class_names.end(), name) != m.class_names.end()) {
        bad(source, "sarmap.classes", *v, "distinct class names (\"" + name + "\" repeats)");
      }
      m.class_names.push_back(name);
      start = comma + 1;
    }
  }
  std::map<std::string, ClassId> mapped;
  if (const auto* v = get("sarmap.class_map")) mapped = parse_class_map(source, *v, m.class_names);
  for (const std::string& name : m.class_names) {
    const auto it = mapped.find(name);
    m.classes.push_back(it != mapped.end() ? it->second : default_sarmap_class(name));
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
  if (!m.class_names.empty()) {
    std::string names;
    nlohmann::json mapped = nlohmann::json::object();
    for (std::size_t l = 0; l < m.class_names.size(); ++l) {
      names += (names.empty() ? "" : ",") + m.class_names[l];
      if (l < m.classes.size() && m.classes[l] != default_sarmap_class(m.class_names[l])) {
        mapped[m.class_names[l]] = std::string(class_info(m.classes[l]).name);
      }
    }
    out["sarmap.classes"] = names;
    if (!mapped.empty()) out["sarmap.class_map"] = mapped.dump();
  }
  return out;
}

}  // namespace sarmap
