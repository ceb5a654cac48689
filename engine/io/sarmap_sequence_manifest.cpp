#include "engine/io/sarmap_sequence_manifest.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/core/error.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/intrinsics.hpp"
#include "engine/io/sha256.hpp"

namespace sarmap {
namespace {

using Json = nlohmann::json;

// Errors name the file and the JSON path of the field: "seq.json: frames[3].pose: ...".
struct Context {
  const std::string& file;

  [[noreturn]] void fail(ErrorCode code, std::string_view field, const std::string& message) const {
    std::string text = file + ": ";
    if (!field.empty()) text += std::string(field) + ": ";
    throw Error(code, text + message);
  }

  void only_keys(const Json& object, std::string_view field,
                 std::initializer_list<std::string_view> keys) const {
    for (const auto& [key, value] : object.items()) {
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
        std::string known;
        for (const auto k : keys) known += (known.empty() ? "" : ", ") + std::string(k);
        fail(ErrorCode::Parse, field, "unknown key \"" + key + "\" (expected one of: " + known + ")");
      }
    }
  }

  const Json& require(const Json& object, std::string_view field, const char* key) const {
    const auto it = object.find(key);
    if (it == object.end()) fail(ErrorCode::Parse, field, std::string("missing key \"") + key + "\"");
    return *it;
  }

  double number(const Json& value, const std::string& field) const {
    if (!value.is_number()) {
      fail(ErrorCode::Parse, field, std::string("expected a number, got ") + value.type_name());
    }
    const double v = value.get<double>();
    if (!std::isfinite(v)) fail(ErrorCode::InvalidData, field, "expected a finite number");
    return v;
  }

  std::vector<double> numbers(const Json& value, const std::string& field, std::size_t count) const {
    if (!value.is_array()) {
      fail(ErrorCode::Parse, field,
           "expected an array of " + std::to_string(count) + " numbers, got " + value.type_name());
    }
    if (value.size() != count) {
      fail(ErrorCode::Parse, field,
           "expected " + std::to_string(count) + " numbers, got " + std::to_string(value.size()));
    }
    std::vector<double> out;
    out.reserve(count);
    for (std::size_t i = 0; i < count; ++i)
      out.push_back(number(value[i], field + "[" + std::to_string(i) + "]"));
    return out;
  }

  int dimension(const Json& value, const std::string& field) const {
    if (!value.is_number_integer() || value.get<long long>() <= 0 || value.get<long long>() > 1'000'000) {
      fail(ErrorCode::InvalidData, field, "expected a positive whole number of pixels");
    }
    return static_cast<int>(value.get<long long>());
  }
};

SensorInfo parse_sensor(const Json& j, const Context& ctx) {
  if (!j.is_object())
    ctx.fail(ErrorCode::Parse, "sensor", std::string("expected an object, got ") + j.type_name());
  ctx.only_keys(j, "sensor", {"type", "max_range", "min_range", "width", "height", "fx", "fy", "cx", "cy"});
  SensorInfo sensor;
  const Json& type = ctx.require(j, "sensor", "type");
  if (type == "depth_camera") {
    sensor.type = SensorType::DepthCamera;
  } else if (type == "lidar") {
    sensor.type = SensorType::Lidar;
  } else {
    ctx.fail(ErrorCode::Parse, "sensor.type", "expected \"depth_camera\" or \"lidar\", got " + type.dump());
  }
  sensor.max_range = ctx.number(ctx.require(j, "sensor", "max_range"), "sensor.max_range");
  if (sensor.max_range < 0) ctx.fail(ErrorCode::InvalidData, "sensor.max_range", "must not be negative");
  if (j.contains("min_range")) {
    sensor.min_range = ctx.number(j["min_range"], "sensor.min_range");
    if (sensor.min_range < 0) ctx.fail(ErrorCode::InvalidData, "sensor.min_range", "must not be negative");
    if (sensor.max_range > 0 && sensor.min_range >= sensor.max_range) {
      ctx.fail(ErrorCode::InvalidData, "sensor.min_range", "must be smaller than sensor.max_range");
    }
  }
  constexpr std::array<const char*, 6> kIntrinsicKeys{"width", "height", "fx", "fy", "cx", "cy"};
  const auto given = std::count_if(kIntrinsicKeys.begin(), kIntrinsicKeys.end(),
                                   [&j](const char* key) { return j.contains(key); });
  if (given > 0) {
    if (given != static_cast<long>(kIntrinsicKeys.size())) {
      ctx.fail(ErrorCode::Parse, "sensor", "intrinsics need all of width, height, fx, fy, cx, cy");
    }
    if (sensor.type != SensorType::DepthCamera) {
      ctx.fail(ErrorCode::InvalidData, "sensor", "intrinsics are only meaningful for a depth_camera");
    }
    PinholeIntrinsics k;
    k.width = ctx.dimension(j["width"], "sensor.width");
    k.height = ctx.dimension(j["height"], "sensor.height");
    k.fx = ctx.number(j["fx"], "sensor.fx");
    k.fy = ctx.number(j["fy"], "sensor.fy");
    k.cx = ctx.number(j["cx"], "sensor.cx");
    k.cy = ctx.number(j["cy"], "sensor.cy");
    validate_intrinsics(k, ctx.file + ": sensor");
    sensor.intrinsics = k;
  }
  return sensor;
}

bool has_point_cloud_extension(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".ply" || ext == ".pcd";
}

SequenceManifestFrame parse_frame(const Json& j, std::size_t index, const Context& ctx) {
  const std::string field = "frames[" + std::to_string(index) + "]";
  if (!j.is_object())
    ctx.fail(ErrorCode::Parse, field, std::string("expected an object, got ") + j.type_name());
  ctx.only_keys(j, field, {"file", "pose", "origin", "timestamp"});
  SequenceManifestFrame frame;
  const Json& file = ctx.require(j, field, "file");
  if (!file.is_string() || file.get<std::string>().empty()) {
    ctx.fail(ErrorCode::Parse, field + ".file",
             std::string("expected a non-empty file name, got ") + file.dump());
  }
  frame.file = file.get<std::string>();
  // Frames live in the sequence's folder: a path that leaves it (absolute, or
  // through "..") would read whatever file it names.
  const std::filesystem::path path(frame.file);
  const bool leaves = path.is_absolute() || path.has_root_name() ||
                      std::any_of(path.begin(), path.end(), [](const std::filesystem::path& part) { return part == ".."; });
  if (leaves) {
    ctx.fail(ErrorCode::Parse, field + ".file", "\"" + frame.file + "\" leaves the sequence's folder (absolute or \"..\")");
  }
  if (!has_point_cloud_extension(frame.file)) {
    ctx.fail(ErrorCode::Parse, field + ".file", "\"" + frame.file + "\" is not a .ply or .pcd file");
  }
  const std::vector<double> pose = ctx.numbers(ctx.require(j, field, "pose"), field + ".pose", 16);
  frame.pose = Pose::from_row_major(pose, ctx.file + ": " + field + ".pose");
  frame.origin = frame.pose.translation();
  if (j.contains("origin")) {
    const std::vector<double> o = ctx.numbers(j["origin"], field + ".origin", 3);
    frame.origin = Eigen::Vector3d(o[0], o[1], o[2]);
  }
  if (j.contains("timestamp")) frame.timestamp = ctx.number(j["timestamp"], field + ".timestamp");
  return frame;
}

}  // namespace

std::string_view to_string(PointsFrame frame) { return frame == PointsFrame::World ? "world" : "sensor"; }

SequenceManifest parse_sequence_manifest(std::string_view json_text, const std::string& file) {
  const Context ctx{file};
  Json j;
  try {
    j = Json::parse(json_text);
  } catch (const Json::exception& e) {  // parse_error, or out_of_range for 1e999
    ctx.fail(ErrorCode::Parse, "", std::string("invalid JSON: ") + e.what());
  }
  if (!j.is_object())
    ctx.fail(ErrorCode::Parse, "", std::string("expected a JSON object, got ") + j.type_name());
  ctx.only_keys(j, "", {"version", "points_frame", "sensor", "frames", "arena_sha256"});
  const Json& version = ctx.require(j, "", "version");
  if (!version.is_number_integer() || version.get<long long>() != kSequenceFormatVersion) {
    ctx.fail(ErrorCode::Unsupported, "version",
             "unsupported sequence version " + version.dump() + " (this build reads version " +
                 std::to_string(kSequenceFormatVersion) + ")");
  }
  SequenceManifest manifest;
  const Json& points_frame = ctx.require(j, "", "points_frame");
  if (points_frame == "world") {
    manifest.points_frame = PointsFrame::World;
  } else if (points_frame == "sensor") {
    manifest.points_frame = PointsFrame::Sensor;
  } else {
    ctx.fail(ErrorCode::Parse, "points_frame",
             "expected \"world\" or \"sensor\", got " + points_frame.dump());
  }
  if (j.contains("sensor")) manifest.sensor = parse_sensor(j["sensor"], ctx);
  if (j.contains("arena_sha256")) {
    const Json& hash = j["arena_sha256"];
    if (!hash.is_string() || !is_sha256_hex(hash.get<std::string>())) {
      ctx.fail(ErrorCode::Parse, "arena_sha256", "expected 64 lowercase hex digits, got " + hash.dump());
    }
    manifest.arena_sha256 = hash.get<std::string>();
  }
  const Json& frames = ctx.require(j, "", "frames");
  if (!frames.is_array())
    ctx.fail(ErrorCode::Parse, "frames", std::string("expected an array, got ") + frames.type_name());
  manifest.frames.reserve(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    manifest.frames.push_back(parse_frame(frames[i], i, ctx));
    // A missing timestamp would read as 0 and put the frame before its predecessors.
    if (i > 0 && frames[i].is_object() &&
        frames[i].contains("timestamp") != frames[0].contains("timestamp")) {
      ctx.fail(ErrorCode::Parse, "frames[" + std::to_string(i) + "]",
               "timestamp given for some frames but not others (give every frame one, or none)");
    }
    if (i > 0 && manifest.frames[i].timestamp < manifest.frames[i - 1].timestamp) {
      std::ostringstream msg;
      msg.precision(17);
      msg << manifest.frames[i].timestamp << " is earlier than frames[" << i - 1 << "].timestamp "
          << manifest.frames[i - 1].timestamp << " (timestamps must not decrease)";
      ctx.fail(ErrorCode::InvalidData, "frames[" + std::to_string(i) + "].timestamp", msg.str());
    }
  }
  return manifest;
}

SequenceManifest read_sequence_manifest(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::Io, path.string() + ": cannot open: " + std::strerror(errno));
  check_input_file_size(path);
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  if (in.bad()) throw Error(ErrorCode::Io, path.string() + ": read failed");
  return parse_sequence_manifest(text, path.string());
}

std::string sequence_manifest_json(const SequenceManifest& manifest) {
  // One frame per line: readable, and a diff shows which frames changed.
  std::string out = "{\n \"version\": " + std::to_string(kSequenceFormatVersion) + ",\n";
  out += " \"points_frame\": \"" + std::string(to_string(manifest.points_frame)) + "\",\n";
  const SensorInfo& s = manifest.sensor;
  if (s.type != SensorType::Unknown) {
    nlohmann::ordered_json sensor;
    sensor["type"] = std::string(to_string(s.type));
    sensor["max_range"] = s.max_range;
    if (s.min_range > 0) sensor["min_range"] = s.min_range;
    if (s.intrinsics) {
      sensor["width"] = s.intrinsics->width;
      sensor["height"] = s.intrinsics->height;
      sensor["fx"] = s.intrinsics->fx;
      sensor["fy"] = s.intrinsics->fy;
      sensor["cx"] = s.intrinsics->cx;
      sensor["cy"] = s.intrinsics->cy;
    }
    out += " \"sensor\": " + sensor.dump() + ",\n";
  }
  if (!manifest.arena_sha256.empty()) out += " \"arena_sha256\": " + Json(manifest.arena_sha256).dump() + ",\n";
  out += " \"frames\": [";
  for (std::size_t i = 0; i < manifest.frames.size(); ++i) {
    const SequenceManifestFrame& f = manifest.frames[i];
    nlohmann::ordered_json frame;
    frame["file"] = f.file;
    const Eigen::Matrix4d m = f.pose.matrix();
    nlohmann::ordered_json pose = nlohmann::ordered_json::array();
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) pose.push_back(m(r, c));
    }
    frame["pose"] = pose;
    frame["origin"] = {f.origin.x(), f.origin.y(), f.origin.z()};
    frame["timestamp"] = f.timestamp;
    out += (i == 0 ? "\n  " : ",\n  ") + frame.dump();
  }
  out += manifest.frames.empty() ? "]\n}\n" : "\n ]\n}\n";
  return out;
}

}  // namespace sarmap
