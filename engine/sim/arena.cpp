#include "engine/sim/arena.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/geometry/float_limits.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/sha256.hpp"
#include "engine/sim/mesh_loader.hpp"

namespace sarmap::sim {
namespace {

using Json = nlohmann::json;

std::string show(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Reads the keys of one JSON object, remembering which were used, so that
// finish() can report the first key nobody asked for.
class Fields {
 public:
  Fields(const Json& object, std::string context) : object_(object), context_(std::move(context)) {
    if (!object_.is_object()) fail_here("must be a JSON object");
  }

  [[noreturn]] void fail(std::string_view key, const std::string& message) const {
    throw Error(ErrorCode::InvalidData, context_ + ": " + std::string(key) + " " + message);
  }
  [[noreturn]] void fail_here(const std::string& message) const {
    throw Error(ErrorCode::InvalidData, context_ + ": " + message);
  }
  const std::string& context() const { return context_; }

  bool has(std::string_view key) const { return object_.contains(std::string(key)); }

  const Json* optional(std::string_view key) {
    const auto it = object_.find(std::string(key));
    if (it == object_.end()) return nullptr;
    used_.insert(std::string(key));
    return &*it;
  }
  const Json& required(std::string_view key) {
    const Json* value = optional(key);
    if (value == nullptr) fail_here("missing required key \"" + std::string(key) + "\"");
    return *value;
  }

  double number_of(std::string_view key, const Json& v) const {
    if (!v.is_number()) fail(key, "must be a number, got " + std::string(v.type_name()));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(key, "must be finite");
    return d;
  }
  double number(std::string_view key) { return number_of(key, required(key)); }
  double number_or(std::string_view key, double fallback) {
    const Json* v = optional(key);
    return v ? number_of(key, *v) : fallback;
  }
  double positive(std::string_view key) {
    const double d = number(key);
    if (!(d > 0)) fail(key, "must be positive, got " + show(d));
    return d;
  }
  double non_negative(std::string_view key) {
    const double d = number(key);
    if (d < 0) fail(key, "must not be negative, got " + show(d));
    return d;
  }
  std::size_t count(std::string_view key, std::size_t min_value) {
    const Json& v = required(key);
    if (!v.is_number_integer()) fail(key, "must be an integer");
    const auto n = v.get<std::int64_t>();
    if (n < static_cast<std::int64_t>(min_value) || n > 1'000'000'000) {
      fail(key, "must be an integer >= " + std::to_string(min_value) + ", got " + std::to_string(n));
    }
    return static_cast<std::size_t>(n);
  }
  std::string string(std::string_view key) {
    const Json& v = required(key);
    if (!v.is_string()) fail(key, "must be a string");
    return v.get<std::string>();
  }
  bool boolean(std::string_view key) {
    const Json& v = required(key);
    if (!v.is_boolean()) fail(key, "must be true or false");
    return v.get<bool>();
  }
  template <int N>
  Eigen::Matrix<double, N, 1> vector_of(std::string_view key, const Json& v) const {
    if (!v.is_array() || v.size() != N) fail(key, "must be an array of " + std::to_string(N) + " numbers");
    Eigen::Matrix<double, N, 1> out;
    for (int i = 0; i < N; ++i) out[i] = number_of(key, v[static_cast<std::size_t>(i)]);
    return out;
  }
  template <int N>
  Eigen::Matrix<double, N, 1> vector(std::string_view key) {
    return vector_of<N>(key, required(key));
  }
  template <int N>
  Eigen::Matrix<double, N, 1> positive_vector(std::string_view key) {
    const auto v = vector<N>(key);
    for (int i = 0; i < N; ++i) {
      if (!(v[i] > 0)) fail(key, "must hold positive sizes, got " + show(v[i]));
    }
    return v;
  }

  // Reports the first key that no reader asked for.
  void finish() const {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      if (!used_.count(it.key())) fail_here("unknown key \"" + it.key() + "\"");
    }
  }

 private:
  const Json& object_;
  std::string context_;
  std::set<std::string> used_;
};

ClassId parse_label(Fields& f, ClassId fallback) {
  const Json* v = f.optional("label");
  if (v == nullptr) return fallback;
  if (!v->is_string()) f.fail("label", "must be a class name string");
  const auto id = class_from_name(v->get<std::string>());
  if (!id || *id == ClassId::Unknown) {
    f.fail("label", "must be one of terrain, wall, inclined_ramp, flat_ramp, other, got \"" +
                        v->get<std::string>() + "\"");
  }
  return *id;
}

ArenaElement parse_element(const Json& j, const std::string& source, std::size_t index,
                           const std::filesystem::path& base_dir) {
  const std::string at = source + ": elements[" + std::to_string(index) + "]";
  if (!j.is_object()) throw Error(ErrorCode::InvalidData, at + ": must be a JSON object");
  const auto type_it = j.find("type");
  if (type_it == j.end() || !type_it->is_string()) {
    throw Error(ErrorCode::InvalidData, at + ": missing required key \"type\" (a string)");
  }
  const std::string type = type_it->get<std::string>();
  Fields f(j, at + " (" + type + ")");
  f.required("type");
  ArenaElement e;
  if (type == "wall") {
    WallSpec w;
    w.from = f.vector<2>("from");
    w.to = f.vector<2>("to");
    w.height = f.positive("height");
    w.thickness = f.positive("thickness");
    if ((w.to - w.from).norm() < 1e-9) f.fail("to", "must differ from from");
    e.shape = w;
    e.label = ClassId::Wall;
  } else if (type == "inclined_ramp") {
    InclinedRampSpec r;
    r.center = f.vector<2>("center");
    r.length = f.positive("length");
    r.width = f.positive("width");
    r.angle_deg = f.number("angle_deg");
    if (!(r.angle_deg > 0 && r.angle_deg < 90)) {
      f.fail("angle_deg", "must be in (0, 90), got " + show(r.angle_deg));
    }
    r.yaw_deg = f.number_or("yaw_deg", 0);
    e.shape = r;
    e.label = ClassId::InclinedRamp;
  } else if (type == "flat_ramp") {
    FlatRampSpec r;
    r.center = f.vector<2>("center");
    r.size = f.positive_vector<2>("size");
    r.height = f.positive("height");
    r.yaw_deg = f.number_or("yaw_deg", 0);
    e.shape = r;
    e.label = ClassId::FlatRamp;
  } else if (type == "box") {
    BoxSpec b;
    b.center = f.vector<3>("center");
    b.size = f.positive_vector<3>("size");
    b.yaw_deg = f.number_or("yaw_deg", 0);
    e.shape = b;
    e.label = parse_label(f, ClassId::Other);
  } else if (type == "mesh") {
    MeshSpec m;
    const std::string relative = f.string("path");
    if (relative.empty()) f.fail("path", "must not be empty");
    m.path = base_dir / relative;
    if (const Json* v = f.optional("position")) m.position = f.vector_of<3>("position", *v);
    if (const Json* v = f.optional("rpy_deg")) m.rpy_deg = f.vector_of<3>("rpy_deg", *v);
    if (const Json* v = f.optional("scale")) {
      m.scale = f.vector_of<3>("scale", *v);
      for (int i = 0; i < 3; ++i) {
        if (!(m.scale[i] > 0)) f.fail("scale", "must hold positive factors, got " + show(m.scale[i]));
      }
    }
    e.label = parse_label(f, ClassId::Other);
    f.finish();
    try {
      LoadedMesh loaded = load_mesh_file(m.path);
      m.vertices = std::move(loaded.vertices);
      m.indices = std::move(loaded.indices);
    } catch (const Error& err) {
      throw Error(err.code(), f.context() + ": path: " + err.what());
    }
    e.shape = std::move(m);
    return e;
  } else {
    throw Error(ErrorCode::InvalidData, at + ": unknown type \"" + type +
                                            "\" (expected wall, inclined_ramp, flat_ramp, box or mesh)");
  }
  f.finish();
  return e;
}

TrajectorySpec parse_trajectory(const Json& j, const std::string& source) {
  Fields f(j, source + ": trajectory");
  TrajectorySpec t;
  if (f.has("poses")) {
    if (f.has("waypoints")) f.fail_here("give either waypoints or poses, not both");
    const Json& poses = f.required("poses");
    if (!poses.is_array() || poses.empty()) f.fail("poses", "must be a non-empty array of 16-number arrays");
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const std::string key = "poses[" + std::to_string(i) + "]";
      const Json& p = poses[i];
      if (!p.is_array() || p.size() != 16) f.fail(key, "must be an array of 16 numbers (row-major 4x4)");
      std::vector<double> values;
      for (const Json& v : p) values.push_back(f.number_of(key, v));
      t.poses.push_back(Pose::from_row_major(values, f.context() + ": " + key));
    }
    t.frames = t.poses.size();
    f.finish();
    return t;
  }
  const Json& waypoints = f.required("waypoints");
  if (!waypoints.is_array() || waypoints.size() < 2) {
    f.fail("waypoints", "must be an array of at least two [x, y] points");
  }
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    t.waypoints.push_back(f.vector_of<2>("waypoints[" + std::to_string(i) + "]", waypoints[i]));
  }
  double length = 0;
  for (std::size_t i = 1; i < t.waypoints.size(); ++i) length += (t.waypoints[i] - t.waypoints[i - 1]).norm();
  if (length < 1e-9) f.fail("waypoints", "must not all be the same point");
  t.height = f.positive("height");
  t.frames = f.count("frames", 1);
  // The trajectory's poses are made up front: 1e8 frames took over 4 GB before the first one.
  if (t.frames > kMaxTrajectoryFrames) {
    f.fail("frames", "must be at most " + std::to_string(kMaxTrajectoryFrames) + ", got " + std::to_string(t.frames));
  }
  t.pitch_deg = f.number_or("pitch_deg", 0);
  if (!(t.pitch_deg > -90 && t.pitch_deg < 90)) f.fail("pitch_deg", "must be in (-90, 90), got " + show(t.pitch_deg));
  f.finish();
  return t;
}

SensorSpec parse_sensor(const Json& j, const std::string& source) {
  Fields f(j, source + ": sensor");
  SensorSpec s;
  const std::string type = f.string("type");
  if (type == "depth_camera") {
    s.type = SensorType::DepthCamera;
    s.intrinsics.width = static_cast<int>(f.count("width", 1));
    s.intrinsics.height = static_cast<int>(f.count("height", 1));
    if (s.intrinsics.width > 16384 || s.intrinsics.height > 16384) f.fail_here("width and height must be at most 16384");
    s.intrinsics.fx = f.positive("fx");
    s.intrinsics.fy = f.positive("fy");
    s.intrinsics.cx = f.number("cx");
    s.intrinsics.cy = f.number("cy");
  } else if (type == "lidar") {
    s.type = SensorType::Lidar;
    s.rings = static_cast<int>(f.count("rings", 1));
    s.horizontal_samples = static_cast<int>(f.count("horizontal_samples", 1));
    if (s.rings > 4096 || s.horizontal_samples > 65536) f.fail_here("rings must be at most 4096 and horizontal_samples at most 65536");
    const Eigen::Vector2d fov = f.vector<2>("vertical_fov_deg");
    if (!(fov[0] >= -90 && fov[1] <= 90 && fov[0] <= fov[1])) {
      f.fail("vertical_fov_deg", "must be [min, max] with -90 <= min <= max <= 90, got [" + show(fov[0]) + ", " +
                                     show(fov[1]) + "]");
    }
    s.vertical_fov_min_deg = fov[0];
    s.vertical_fov_max_deg = fov[1];
  } else {
    f.fail("type", "must be \"depth_camera\" or \"lidar\", got \"" + type + "\"");
  }
  s.min_range = f.non_negative("min_range");
  s.max_range = f.positive("max_range");
  if (!(s.max_range > s.min_range)) f.fail("max_range", "must be greater than min_range");
  if (const Json* noise = f.optional("noise")) {
    if (!noise->is_string()) f.fail("noise", "must be \"none\", \"gaussian\" or \"kinect\"");
    const std::string kind = noise->get<std::string>();
    if (kind == "none") {
      s.noise.kind = NoiseKind::None;
    } else if (kind == "gaussian") {
      s.noise.kind = NoiseKind::Gaussian;
      s.noise.sigma = f.non_negative("sigma");
    } else if (kind == "kinect") {
      s.noise.kind = NoiseKind::Kinect;
    } else {
      f.fail("noise", "must be \"none\", \"gaussian\" or \"kinect\", got \"" + kind + "\"");
    }
  }
  if (const Json* dropout = f.optional("dropout")) {
    s.noise.dropout = f.number_of("dropout", *dropout);
    if (!(s.noise.dropout >= 0 && s.noise.dropout < 1)) {
      f.fail("dropout", "must be in [0, 1), got " + show(s.noise.dropout));
    }
  }
  f.finish();
  return s;
}

}  // namespace

std::string_view element_type_name(const ArenaElement& element) {
  static constexpr std::string_view kNames[] = {"wall", "inclined_ramp", "flat_ramp", "box", "mesh"};
  return kNames[element.shape.index()];
}

Arena parse_arena(std::string_view json_text, std::string_view source_view,
                  const std::filesystem::path& base_dir) {
  const std::string source(source_view);
  Json j;
  try {
    j = Json::parse(json_text.begin(), json_text.end());
  } catch (const Json::parse_error& e) {
    throw Error(ErrorCode::Parse, source + " (byte offset " + std::to_string(e.byte) + "): not valid JSON: " + e.what());
  } catch (const Json::exception& e) {  // out_of_range: a number beyond a double, such as 1e999
    throw Error(ErrorCode::Parse, source + ": not valid JSON: " + e.what());
  }
  Fields f(j, source);
  Arena a;
  a.source = source;
  a.sha256 = sha256_hex(json_text);
  if (const Json* v = f.optional("version")) {
    if (!v->is_number_integer() || v->get<std::int64_t>() != 1) f.fail("version", "must be 1");
  }
  a.name = f.string("name");
  if (a.name.empty()) f.fail("name", "must not be empty");
  {
    Fields b(f.required("bounds"), source + ": bounds");
    a.bounds_min = b.vector<3>("min");
    a.bounds_max = b.vector<3>("max");
    b.finish();
    for (int i = 0; i < 3; ++i) {
      if (!(a.bounds_max[i] > a.bounds_min[i])) b.fail("max", "must exceed min on every axis");
    }
    // Rays start at the bounds (the trajectory's ground test casts down from
    // their top): Embree's float rays are refused beyond the scene limit.
    for (const char* key : {"min", "max"}) {
      const Eigen::Vector3d& v = std::string_view(key) == "min" ? a.bounds_min : a.bounds_max;
      if (v.cwiseAbs().maxCoeff() > geometry::kMaxSceneCoordinate) {
        b.fail(key, "must lie within " + show(geometry::kMaxSceneCoordinate) + " m of the origin on every axis");
      }
    }
  }
  a.floor = f.boolean("floor");
  const Json& elements = f.required("elements");
  if (!elements.is_array()) f.fail("elements", "must be an array");
  for (std::size_t i = 0; i < elements.size(); ++i) {
    a.elements.push_back(parse_element(elements[i], source, i, base_dir));
  }
  a.trajectory = parse_trajectory(f.required("trajectory"), source);
  a.sensor = parse_sensor(f.required("sensor"), source);
  if (const Json* pairs = f.optional("eval_pairs")) {
    if (!pairs->is_array()) f.fail("eval_pairs", "must be an array of [[x, y, z], [x, y, z]] pairs");
    for (std::size_t i = 0; i < pairs->size(); ++i) {
      const std::string key = "eval_pairs[" + std::to_string(i) + "]";
      const Json& p = (*pairs)[i];
      if (!p.is_array() || p.size() != 2) f.fail(key, "must be a pair [[x, y, z], [x, y, z]]");
      a.eval_pairs.emplace_back(f.vector_of<3>(key, p[0]), f.vector_of<3>(key, p[1]));
    }
  }
  f.finish();
  return a;
}

Arena load_arena(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::Io, path.string() + ": cannot open arena file");
  check_input_file_size(path);
  std::ostringstream text;
  text << in.rdbuf();
  return parse_arena(text.str(), path.string(), path.parent_path());
}

SensorInfo sensor_info(const SensorSpec& sensor) {
  SensorInfo info;
  info.type = sensor.type;
  info.min_range = sensor.min_range;
  info.max_range = sensor.max_range;
  if (sensor.type == SensorType::DepthCamera) info.intrinsics = sensor.intrinsics;
  return info;
}

}  // namespace sarmap::sim
