// `sarmap info FILE|FOLDER`: what a point cloud or a scan sequence holds —
// points, bounds, fields, classes; for a sequence also its layout, sensor and
// pose range. Sequences are read frame by frame, so any size fits in memory.
// A metric map (map.sarmap): resolution, blocks, voxels by state, occupied
// voxels by class and the extent of what is known and occupied.
#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "engine/core/bounds.hpp"
#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/metric/map_summary.hpp"
#include "tools/sarmap/commands.hpp"
#include "tools/sarmap/progress.hpp"
#include "tools/sarmap/sequence_input_options.hpp"

namespace sarmap::cli {
namespace {

using Json = nlohmann::ordered_json;

struct InfoArgs {
  std::string path;
  bool json = false;
  bool quiet = false;
  SequenceInputArgs sequence;
};

using ClassCounts = std::array<std::size_t, kClassCount>;

void count_classes(const PointBuffer& points, ClassCounts& counts) {
  if (!points.has_labels()) return;
  for (const std::uint8_t label : points.labels()) {
    if (label < kClassCount) ++counts[label];
  }
}

Json vec3(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json bounds_json(const Bounds& b) {
  if (b.empty()) return nullptr;
  return Json{{"min", vec3(b.min)}, {"max", vec3(b.max)}, {"size", vec3(b.size())}};
}

Json classes_json(const ClassCounts& counts) {
  Json out = Json::object();
  for (const ClassInfo& c : kClassTable) out[std::string(c.name)] = counts[static_cast<std::size_t>(c.id)];
  return out;
}

std::string vec3_text(const Eigen::Vector3d& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.3f, %.3f, %.3f)", v.x(), v.y(), v.z());
  return text;
}

void print_bounds(const char* label, const Bounds& b) {
  if (b.empty()) {
    std::printf("%s: empty\n", label);
    return;
  }
  std::printf("%s: min %s  max %s  size %s\n", label, vec3_text(b.min).c_str(), vec3_text(b.max).c_str(),
              vec3_text(b.size()).c_str());
}

void print_classes(const ClassCounts& counts) {
  std::printf("classes:");
  for (const ClassInfo& c : kClassTable) {
    std::printf(" %s %zu", std::string(c.name).c_str(), counts[static_cast<std::size_t>(c.id)]);
  }
  std::printf("\n");
}

std::string_view format_name(PointCloudFormat f) { return f == PointCloudFormat::Ply ? "ply" : "pcd"; }

void map_info(const InfoArgs& a) {
  const metric::MapFile file = metric::read_map_file(a.path);
  const metric::MetricMap& map = file.map;
  const metric::MapSummary s = metric::summarize_map(map);
  const std::string_view fusion = metric::to_string(map.settings().fusion.fusion);
  if (a.json) {
    Json j;
    j["path"] = a.path;
    j["kind"] = "metric_map";
    j["format"] = "sarmap";
    j["version"] = file.version;
    j["resolution"] = map.resolution();
    j["class_fusion"] = fusion;
    j["blocks"] = s.counts.blocks;
    j["uniform_blocks"] = s.uniform_blocks;
    j["blocks_in_uniform_groups"] = s.blocks_in_uniform_groups;
    j["voxels"] = Json{{"known", s.counts.known}, {"free", s.counts.free}, {"occupied", s.counts.occupied}};
    j["occupied_classes"] = classes_json(s.occupied_by_class);
    j["bounds"] = Json{{"known", bounds_json(s.known_bounds)}, {"occupied", bounds_json(s.occupied_bounds)}};
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("file: %s\n", a.path.c_str());
  std::printf("format: sarmap metric map (version %u)\n", file.version);
  std::printf("resolution: %g m\n", map.resolution());
  std::printf("class fusion: %s\n", std::string(fusion).c_str());
  std::printf("blocks: %zu (8 x 8 x 8 voxels each), %zu uniform (one value, no class evidence), %zu of them in whole "
              "2 x 2 x 2 groups of one value\n",
              s.counts.blocks, s.uniform_blocks, s.blocks_in_uniform_groups);
  std::printf("voxels: %zu known: %zu free, %zu occupied\n", s.counts.known, s.counts.free, s.counts.occupied);
  std::printf("occupied ");
  print_classes(s.occupied_by_class);
  print_bounds("known bounds", s.known_bounds);
  print_bounds("occupied bounds", s.occupied_bounds);
}

void cloud_info(const InfoArgs& a) {
  PointCloudFileInfo info;
  const PointBuffer points = read_point_cloud(a.path, &info, a.sequence.options().limits);
  const Bounds bounds = points.bounds();
  ClassCounts classes{};
  count_classes(points, classes);
  if (a.json) {
    Json j;
    j["path"] = a.path;
    j["kind"] = "cloud";
    j["format"] = format_name(info.format);
    j["encoding"] = info.encoding;
    j["points"] = points.size();
    j["points_in_file"] = info.points_in_file;
    j["dropped_non_finite"] = info.dropped_non_finite;
    j["fields"] = info.fields;
    j["comments"] = info.comments;
    j["bounds"] = bounds_json(bounds);
    if (points.has_labels()) j["classes"] = classes_json(classes);
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("file: %s\n", a.path.c_str());
  std::printf("format: %s (%s)\n", std::string(format_name(info.format)).c_str(), info.encoding.c_str());
  std::printf("points: %zu", points.size());
  if (info.dropped_non_finite > 0) {
    std::printf(" (%zu in the file, %zu dropped for NaN/Inf coordinates)", info.points_in_file,
                info.dropped_non_finite);
  }
  std::printf("\nfields:");
  for (const auto& f : info.fields) std::printf(" %s", f.c_str());
  std::printf("\n");
  for (const auto& c : info.comments) std::printf("comment: %s\n", c.c_str());
  print_bounds("bounds", bounds);
  if (points.has_labels()) print_classes(classes);
}

Json sensor_json(const SensorInfo& s) {
  Json j;
  j["type"] = to_string(s.type);
  j["min_range"] = s.min_range;
  j["max_range"] = s.max_range;
  if (s.intrinsics) {
    const PinholeIntrinsics& k = *s.intrinsics;
    j["intrinsics"] = Json{{"width", k.width}, {"height", k.height}, {"fx", k.fx},
                           {"fy", k.fy},       {"cx", k.cx},         {"cy", k.cy}};
  }
  return j;
}

std::string sensor_text(const SensorInfo& s) {
  std::string out(to_string(s.type));
  char text[160];
  if (s.max_range > 0) {
    std::snprintf(text, sizeof text, ", range %g-%g m", s.min_range, s.max_range);
    out += text;
  }
  if (s.intrinsics) {
    const PinholeIntrinsics& k = *s.intrinsics;
    std::snprintf(text, sizeof text, ", pinhole %dx%d fx %g fy %g cx %g cy %g", k.width, k.height, k.fx, k.fy,
                  k.cx, k.cy);
    out += text;
  }
  return out;
}

void sequence_info(const InfoArgs& a) {
  const std::unique_ptr<ScanSource> source = open_input_sequence(a.path, a.sequence);

  std::size_t total_points = 0, dropped = 0, frames = 0;
  Bounds bounds, positions;
  double path_length = 0, first_time = 0, last_time = 0;
  std::optional<Eigen::Vector3d> previous;
  ClassCounts classes{};
  bool labelled = false;
  std::size_t unreadable = 0;
  std::string first_unreadable;
  {
    ProgressLine progress("info", source->size(), !a.quiet);
    Scan scan;
    // A frame that cannot be read is counted and passed over, as `run` skips
    // it: the source has moved past it (ScanSource::next).
    while (true) {
      try {
        if (!source->next(scan)) break;
      } catch (const Error& e) {
        if (unreadable++ == 0) first_unreadable = e.what();
        progress.update(frames + unreadable);  // frames read so far, readable or not
        continue;
      }
      total_points += scan.points.size();
      dropped += scan.dropped_non_finite;
      bounds.extend(scan.points.bounds());
      const Eigen::Vector3d position = scan.pose.translation();
      positions.extend(position);
      if (previous) path_length += (position - *previous).norm();
      previous = position;
      if (frames == 0) first_time = scan.timestamp;
      last_time = scan.timestamp;
      labelled = labelled || scan.points.has_labels();
      count_classes(scan.points, classes);
      progress.update(++frames + unreadable);
    }
  }

  if (frames == 0 && unreadable > 0) {
    throw Error(ErrorCode::InvalidData, "info: none of the " + std::to_string(unreadable) +
                                            " frames could be read; the first: " + first_unreadable);
  }
  if (a.json) {
    Json j;
    j["path"] = a.path;
    j["kind"] = "sequence";
    j["layout"] = source->layout();
    j["frames"] = frames;
    j["skipped_frames"] = source->skipped_frames();
    j["unreadable_frames"] = unreadable;
    j["first_unreadable"] = unreadable > 0 ? Json(first_unreadable) : Json(nullptr);
    j["sensor"] = sensor_json(source->sensor());
    j["points"] = total_points;
    j["dropped_non_finite"] = dropped;
    j["bounds"] = bounds_json(bounds);
    j["poses"] = Json{{"translation_min", positions.empty() ? Json(nullptr) : vec3(positions.min)},
                      {"translation_max", positions.empty() ? Json(nullptr) : vec3(positions.max)},
                      {"path_length", path_length}};
    j["time"] = Json{{"first", first_time}, {"last", last_time}};
    if (labelled) j["classes"] = classes_json(classes);
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("sequence: %s\n", a.path.c_str());
  std::printf("layout: %s\n", source->layout().c_str());
  std::printf("frames: %zu", frames);
  if (source->skipped_frames() > 0) {
    std::printf(" (%zu more skipped: no pose within %g s)", source->skipped_frames(),
                a.sequence.max_time_difference);
  }
  if (unreadable > 0) std::printf(" (%zu unreadable, the first: %s)", unreadable, first_unreadable.c_str());
  std::printf("\nsensor: %s\n", sensor_text(source->sensor()).c_str());
  std::printf("points: %zu", total_points);
  if (dropped > 0) std::printf(" (%zu dropped for NaN/Inf coordinates)", dropped);
  std::printf("\n");
  print_bounds("bounds", bounds);
  if (!positions.empty()) {
    std::printf("poses: translation min %s  max %s  path length %.3f m\n", vec3_text(positions.min).c_str(),
                vec3_text(positions.max).c_str(), path_length);
  }
  std::printf("time: %.6f to %.6f s (%.3f s)\n", first_time, last_time, last_time - first_time);
  if (labelled) print_classes(classes);
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "info", "Describe a point cloud (.ply, .pcd), a metric map (map.sarmap) or a scan sequence folder");
  cmd->add_option(
         "path", args->path,
         "PLY / PCD file, a metric map (.sarmap), a sequence folder (sarmap, TUM RGB-D, 7-Scenes) or "
         "a ROS 1 bag (.bag)")
      ->required();
  cmd->add_flag("--json", args->json, "Machine-readable output");
  add_sequence_input_options(cmd, args->sequence);
  cmd->add_flag("--quiet", args->quiet, "No progress line");
  cmd->callback([args] {
    const std::filesystem::path path(args->path);
    if (metric::is_map_file_path(path) && !std::filesystem::is_directory(path)) {
      map_info(*args);
    } else if (std::filesystem::is_regular_file(path) && path.filename() != "sequence.json" &&
               !is_bag_path(path)) {
      cloud_info(*args);
    } else {
      sequence_info(*args);
    }
  });
}

}  // namespace sarmap::cli
