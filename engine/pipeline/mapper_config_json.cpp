#include "engine/pipeline/mapper_config_json.hpp"

#include <cmath>
#include <cstdint>
#include <set>
#include <type_traits>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/json_fields.hpp"

namespace sarmap::pipeline {

namespace {

using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

// The schema: every setting once, in the order files list them. `v` is a
// JsonWriter (C = const MapperConfig) or a JsonReader (C = MapperConfig).
// map.resolution and integrator.max_range are left out: the Mapper takes
// them from voxel and max_range.
template <class V, class C>
void visit_config(V& v, C& c) {
  v.field("voxel", c.voxel);
  v.field("max_range", c.max_range);
  v.field("max_point_distance", c.max_point_distance);
  v.field("semantic_points_voxel", c.semantic_points_voxel);
  v.field("segment_max_range_lidar", c.segment_max_range_lidar);
  v.group("bounds", [&] {
    v.field("keep_radius", c.bounds.keep_radius);
    v.field("max_blocks", c.bounds.max_blocks);
  });
  auto& k = c.classifier;
  v.group("classifier", [&] {
    v.field("kind", k.kind);
    v.field("model", k.model);
    v.field("per_scan", k.per_scan);
    v.field("map_cell", k.map_cell);
    v.field("map_growth", k.map_growth);
    v.field("map_min_new_points", k.map_min_new_points);
    v.field("map_max_wait_scans", k.map_max_wait_scans);
    v.group("dgcnn", [&] {
      v.field("stride", k.dgcnn.stride);
      v.field("min_points", k.dgcnn.min_points);
      v.field("seed", k.dgcnn.seed);
      // The rules keep their places of before they were one chain
      // (classifier.rules), so that earlier config files still read.
      v.group("ramp_veto", [&] {
        v.field("enabled", k.rules.ramp_veto.enabled);
        v.field("cell", k.rules.ramp_veto.cell);
        v.field("min_slope_deg", k.rules.ramp_veto.min_slope_deg);
        v.field("min_points", k.rules.ramp_veto.min_points);
      });
    });
    v.group("wall_bands", [&] {
      v.field("enabled", k.rules.wall_bands.enabled);
      v.field("column", k.rules.wall_bands.column);
      v.field("min_length", k.rules.wall_bands.min_length);
    });
    v.group("ramp_sides", [&] {
      v.field("enabled", k.rules.ramp_sides.enabled);
      v.field("radius", k.rules.ramp_sides.radius);
      v.field("min_rise", k.rules.ramp_sides.min_rise);
      v.field("max_rise", k.rules.ramp_sides.max_rise);
      v.field("deck_max_slope_deg", k.rules.ramp_sides.deck_max_slope_deg);
      v.field("deck_max_curvature", k.rules.ramp_sides.deck_max_curvature);
      v.field("normal_cell", k.rules.ramp_sides.normal_cell);
      v.field("min_points", k.rules.ramp_sides.min_points);
    });
    v.group("wall_feet", [&] {
      v.field("enabled", k.rules.wall_feet.enabled);
      v.field("column", k.rules.wall_feet.column);
      v.field("tolerance", k.rules.wall_feet.tolerance);
      v.field("min_floor_points", k.rules.wall_feet.min_floor_points);
    });
    auto& g = k.geometric;
    v.group("geometric", [&] {
      v.group("normals", [&] {
        v.field("cell", g.normals.cell);
        v.field("min_points", g.normals.min_points);
        v.field("max_curvature", g.normals.max_curvature);
      });
      v.group("floor", [&] {
        v.field("column", g.floor.column);
        v.field("window", g.floor.window);
        v.field("max_floor_slope_deg", g.floor.max_floor_slope_deg);
      });
      v.field("horizontal_max_deg", g.horizontal_max_deg);
      v.field("inclined_max_deg", g.inclined_max_deg);
      v.field("vertical_min_deg", g.vertical_min_deg);
      v.field("raised_min_height", g.raised_min_height);
      v.field("flat_ramp_max_height", g.flat_ramp_max_height);
      v.field("wall_min_height", g.wall_min_height);
      v.field("edge_curvature", g.edge_curvature);
      v.field("side_tolerance", g.side_tolerance);
    });
  });
  v.group("map", [&] {
    v.group("occupancy", [&] {
      v.field("prob_hit", c.map.occupancy.prob_hit);
      v.field("prob_miss", c.map.occupancy.prob_miss);
      v.field("clamp_min", c.map.occupancy.clamp_min);
      v.field("clamp_max", c.map.occupancy.clamp_max);
      v.field("occupied_threshold", c.map.occupancy.occupied_threshold);
    });
    v.group("fusion", [&] {
      v.field("fusion", c.map.fusion.fusion);
      v.field("label_confidence", c.map.fusion.label_confidence);
      v.field("evidence_clamp", c.map.fusion.evidence_clamp);
      v.field("free_evidence_keep", c.map.fusion.free_evidence_keep);
    });
  });
  v.group("integrator", [&] {
    v.field("clear_beyond_max_range", c.integrator.clear_beyond_max_range);
    v.field("discretize", c.integrator.discretize);
    v.field("use_scores", c.integrator.use_scores);
    v.field("dense_walk_max_blocks", c.integrator.dense_walk_max_blocks);
    v.field("dense_dedupe_max_cells", c.integrator.dense_dedupe_max_cells);
  });
  v.group("segments", [&] {
    v.field("voxel", c.segments.voxel);
    v.field("distance_threshold", c.segments.distance_threshold);
    v.field("confidence", c.segments.confidence);
    v.field("max_iterations", c.segments.max_iterations);
    v.field("min_points", c.segments.min_points);
    v.field("cluster_radius", c.segments.cluster_radius);
    v.field("merge_angle_deg", c.segments.merge_angle_deg);
    v.field("merge_overlap_angle_deg", c.segments.merge_overlap_angle_deg);
    v.field("merge_offset", c.segments.merge_offset);
    v.field("merge_gap", c.segments.merge_gap);
    v.field("max_range", c.segments.max_range);
    v.field("closer_view_ratio", c.segments.closer_view_ratio);
    v.field("max_search_rounds", c.segments.max_search_rounds);
    v.field("seed", c.segments.seed);
  });
  v.group("topo", [&] {
    v.field("robot_radius", c.topo.robot_radius);
    v.field("robot_height", c.topo.robot_height);
    v.field("body_heights", c.topo.body_heights);
    v.field("max_slope_deg", c.topo.max_slope_deg);
    v.field("max_step", c.topo.max_step);
    v.field("node_spacing", c.topo.node_spacing);
    v.field("edge_radius", c.topo.edge_radius);
    v.field("obstacle_voxels", c.topo.obstacle_voxels);
    v.field("unknown_traversable", c.topo.unknown_traversable);
  });
}

const char* fusion_name(metric::ClassFusion f) {
  return f == metric::ClassFusion::Bayesian ? "bayesian" : "histogram";
}

class JsonWriter {
 public:
  Json take() { return std::move(current_); }

  template <class T>
  void field(const char* key, const T& value) {
    if constexpr (std::is_same_v<T, fs::path>) {
      current_[key] = value.string();
    } else if constexpr (std::is_same_v<T, metric::ClassFusion>) {
      current_[key] = fusion_name(value);
    } else if constexpr (std::is_same_v<T, ClassifierKind>) {
      current_[key] = std::string(to_string(value));
    } else {
      current_[key] = value;
    }
  }

  template <class Body>
  void group(const char* key, Body&& body) {
    Json parent = std::move(current_);
    current_ = Json::object();
    body();
    parent[key] = std::move(current_);
    current_ = std::move(parent);
  }

 private:
  Json current_ = Json::object();
};

class JsonReader {
 public:
  JsonReader(const Json& root, std::string source) : source_(std::move(source)) { levels_.push_back({&root, "", {}}); }

  template <class T>
  void field(const char* key, T& value) {
    if (const Json* j = take(key)) read(*j, dotted(key), value);
  }

  template <class Body>
  void group(const char* key, Body&& body) {
    const Json* j = take(key);
    if (j == nullptr) return;  // the whole group at its defaults
    if (!j->is_object()) fail(dotted(key), "must be an object, got " + j->dump());
    levels_.push_back({j, dotted(key) + ".", {}});
    body();
    refuse_unknown_keys();
    levels_.pop_back();
  }

  // The key marked as read, so refuse_unknown_keys() lets it pass.
  const Json* take(const char* key) {
    Level& level = levels_.back();
    const auto it = level.object->find(key);
    if (it == level.object->end()) return nullptr;
    level.read.insert(key);
    return &*it;
  }

  void refuse_unknown_keys() const {
    const Level& level = levels_.back();
    for (const auto& [key, value] : level.object->items()) {
      if (level.read.count(key) == 0) fail(level.prefix + key, "unknown key");
    }
  }

  std::string dotted(const char* key) const { return levels_.back().prefix + key; }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw Error(ErrorCode::InvalidData, source_ + ": " + key + ": " + what);
  }

 private:
  struct Level {
    const Json* object;
    std::string prefix;  // "classifier.dgcnn." for keys inside that group
    std::set<std::string> read;
  };

  void read(const Json& j, const std::string& key, double& value) const {
    if (!j.is_number()) fail(key, "must be a number, got " + j.dump());
    value = j.get<double>();
  }
  void read(const Json& j, const std::string& key, bool& value) const {
    if (!j.is_boolean()) fail(key, "must be true or false, got " + j.dump());
    value = j.get<bool>();
  }
  void read(const Json& j, const std::string& key, std::string& value) const {
    if (!j.is_string()) fail(key, "must be a string, got " + j.dump());
    value = j.get<std::string>();
  }
  void read(const Json& j, const std::string& key, fs::path& value) const {
    std::string text;
    read(j, key, text);
    value = text;
  }
  // Whole numbers >= 0; 1e3 is accepted as 1000, 2.5 and -1 are not.
  template <class Unsigned>
    requires std::is_unsigned_v<Unsigned>
  void read(const Json& j, const std::string& key, Unsigned& value) const {
    if (j.is_number_unsigned()) {
      value = static_cast<Unsigned>(j.get<std::uint64_t>());
      return;
    }
    constexpr double kExactLimit = 9007199254740992.0;  // 2^53
    if (j.is_number_float()) {
      const double d = j.get<double>();
      if (d >= 0 && d <= kExactLimit && std::floor(d) == d) {
        value = static_cast<Unsigned>(d);
        return;
      }
    }
    fail(key, "must be a whole number >= 0, got " + j.dump());
  }
  void read(const Json& j, const std::string& key, std::vector<double>& value) const {
    if (!j.is_array()) fail(key, "must be an array of numbers, got " + j.dump());
    std::vector<double> out;
    for (const Json& item : j) {
      if (!item.is_number()) fail(key, "must be an array of numbers, got " + j.dump());
      out.push_back(item.get<double>());
    }
    value = std::move(out);
  }
  void read(const Json& j, const std::string& key, ClassifierKind& value) const {
    std::string name;
    read(j, key, name);
    try {
      value = classifier_kind_from_name(name);
    } catch (const Error&) {
      fail(key, "must be \"dgcnn\", \"geometric\" or \"labels\", got " + j.dump());
    }
  }
  void read(const Json& j, const std::string& key, metric::ClassFusion& value) const {
    std::string name;
    read(j, key, name);
    if (name == "bayesian") {
      value = metric::ClassFusion::Bayesian;
    } else if (name == "histogram") {
      value = metric::ClassFusion::Histogram;
    } else {
      fail(key, "must be \"bayesian\" or \"histogram\", got " + j.dump());
    }
  }

  std::string source_;
  std::vector<Level> levels_;
};

}  // namespace

Json config_to_json(const MapperConfig& config) {
  JsonWriter writer;
  writer.field("version", kConfigVersion);
  visit_config(writer, config);
  return writer.take();
}

MapperConfig config_from_json(const Json& json, const MapperConfig& base, const std::string& source) {
  if (!json.is_object()) throw Error(ErrorCode::InvalidData, source + ": a config must be a JSON object");
  MapperConfig config = base;
  JsonReader reader(json, source);
  if (const Json* version = reader.take("version")) {
    if (!version->is_number_integer() || version->get<std::int64_t>() != kConfigVersion) {
      reader.fail("version", "this sarmap reads config version " + std::to_string(kConfigVersion) + ", got " +
                                 version->dump());
    }
  }
  visit_config(reader, config);
  reader.refuse_unknown_keys();
  return config;
}

MapperConfig read_config_file(const fs::path& path, const MapperConfig& base) {
  const Json file = json_fields::read_file(path);
  const bool manifest = file.is_object() && file.contains("config");
  if (!manifest && file.is_object() && file.contains("outputs")) {
    throw Error(ErrorCode::InvalidData, path.string() +
                                            ": a manifest without a \"config\" member (written by an older "
                                            "sarmap): give a config file instead");
  }
  MapperConfig config = config_from_json(manifest ? file.at("config") : file, base, path.string());
  if (!config.classifier.model.empty() && config.classifier.model.is_relative()) {
    config.classifier.model = path.parent_path() / config.classifier.model;
  }
  return config;
}

}  // namespace sarmap::pipeline
