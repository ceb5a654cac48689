#include "engine/segments/segment_files.hpp"

#include "engine/io/atomic_file.hpp"
#include "engine/io/json_fields.hpp"
#include "engine/io/ply_mesh.hpp"

namespace sarmap::segments {
namespace {

using json_fields::Json;
using json_fields::fail;
using json_fields::member;
using json_fields::number;
using json_fields::vector3;

Json vec(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json segment_json(const Segment& s) {
  Json j;
  j["id"] = s.id;
  j["class"] = class_info(s.label).name;
  j["class_id"] = static_cast<int>(s.label);
  j["normal"] = vec(s.plane.normal);
  j["offset"] = s.plane.offset;
  j["centroid"] = vec(s.centroid);
  j["slope_deg"] = s.slope_deg;
  j["area_m2"] = s.area_m2;
  j["inliers"] = s.inliers;
  j["thickness"] = s.thickness;
  j["rectangle"] = {{"center", vec(s.rectangle.center)},
                    {"axes", Json::array({vec(s.rectangle.axes[0]), vec(s.rectangle.axes[1])})},
                    {"half_extents", Json::array({s.rectangle.half_extents[0], s.rectangle.half_extents[1]})}};
  j["min"] = vec(s.min);
  j["max"] = vec(s.max);
  return j;
}

Segment parse_segment(const Json& j, const std::filesystem::path& path, const std::string& where) {
  Segment s;
  const Json& id = member(j, "id", path, where);
  if (!id.is_number_unsigned()) fail(path, where, "\"id\" is not an unsigned integer");
  s.id = id.get<std::uint32_t>();
  const Json& label = member(j, "class", path, where);
  const auto c = label.is_string() ? class_from_name(label.get<std::string>()) : std::nullopt;
  if (!c) fail(path, where, "\"class\" is not a class name");
  s.label = *c;
  s.plane.normal = vector3(member(j, "normal", path, where), "normal", path, where);
  s.plane.offset = number(j, "offset", path, where);
  s.centroid = vector3(member(j, "centroid", path, where), "centroid", path, where);
  s.slope_deg = number(j, "slope_deg", path, where);
  s.area_m2 = number(j, "area_m2", path, where);
  s.inliers = static_cast<std::size_t>(number(j, "inliers", path, where));
  s.thickness = number(j, "thickness", path, where);
  const Json& r = member(j, "rectangle", path, where);
  s.rectangle.center = vector3(member(r, "center", path, where), "rectangle.center", path, where);
  const Json& axes = member(r, "axes", path, where);
  const Json& half = member(r, "half_extents", path, where);
  if (!axes.is_array() || axes.size() != 2) fail(path, where, "\"rectangle.axes\" is not two vectors");
  if (!half.is_array() || half.size() != 2 || !half[0].is_number() || !half[1].is_number()) {
    fail(path, where, "\"rectangle.half_extents\" is not two numbers");
  }
  for (int a = 0; a < 2; ++a) {
    s.rectangle.axes[a] = vector3(axes[a], "rectangle.axes", path, where);
    s.rectangle.half_extents[a] = half[a].get<double>();
  }
  s.min = vector3(member(j, "min", path, where), "min", path, where);
  s.max = vector3(member(j, "max", path, where), "max", path, where);
  return s;
}

}  // namespace

std::string segments_json(const SegmentMap& map) {
  Json j;
  j["version"] = kSegmentsFormatVersion;
  j["segments"] = Json::array();
  for (const Segment* s : map.segments()) j["segments"].push_back(segment_json(*s));
  j["merges"] = Json::array();
  for (const auto& [absorbed, survivor] : map.merges()) j["merges"].push_back(Json::array({absorbed, survivor}));
  return j.dump(1) + "\n";
}

void write_segments_json(const std::filesystem::path& path, const SegmentMap& map) {
  AtomicFileWriter out(path);
  out.write(segments_json(map));
  out.commit();
}

void write_segments_ply(const std::filesystem::path& path, const SegmentMap& map) {
  ColoredMesh mesh;
  for (const Segment* s : map.segments()) {
    const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
    for (const Eigen::Vector3d& corner : s->rectangle.corners()) {
      mesh.vertices.push_back(corner.cast<float>());
      mesh.vertex_colors.push_back(class_info(s->label).color);
    }
    mesh.faces.push_back({first, first + 1, first + 2, first + 3});
  }
  write_ply_mesh(path, mesh);
}

SegmentsFile read_segments_json(const std::filesystem::path& path) {
  const Json j = json_fields::read_file(path);
  const Json& version = member(j, "version", path, "top level");
  if (!version.is_number_integer() || version.get<int>() != kSegmentsFormatVersion) {
    fail(path, "top level", "\"version\" must be " + std::to_string(kSegmentsFormatVersion));
  }
  SegmentsFile file;
  const Json& list = member(j, "segments", path, "top level");
  if (!list.is_array()) fail(path, "top level", "\"segments\" is not an array");
  for (std::size_t i = 0; i < list.size(); ++i) {
    file.segments.push_back(parse_segment(list[i], path, "segments[" + std::to_string(i) + "]"));
  }
  if (j.contains("merges")) {
    const Json& merges = j["merges"];
    if (!merges.is_array()) fail(path, "top level", "\"merges\" is not an array");
    for (std::size_t i = 0; i < merges.size(); ++i) {
      const Json& m = merges[i];
      if (!m.is_array() || m.size() != 2 || !m[0].is_number_unsigned() || !m[1].is_number_unsigned()) {
        fail(path, "merges[" + std::to_string(i) + "]", "not two ids");
      }
      file.merges.emplace_back(m[0].get<std::uint32_t>(), m[1].get<std::uint32_t>());
    }
  }
  return file;
}

}  // namespace sarmap::segments
