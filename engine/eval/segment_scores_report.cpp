// The segment figures as JSON, as the eval table's section and as the demo's
// one line (declared in segment_scores.hpp).
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/eval/optional_json_number.hpp"
#include "engine/eval/segment_scores.hpp"

namespace sarmap::eval {
namespace {

using Json = nlohmann::ordered_json;

Json vec(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

std::string fixed(const char* format, double v) {
  char text[48];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

std::string ids(const std::vector<std::uint32_t>& list) {
  std::string s;
  for (std::uint32_t id : list) s += (s.empty() ? "" : " ") + std::to_string(id);
  return s.empty() ? "-" : s;
}

// -0.00 reads as a different direction from 0.00.
double tidy(double v) { return std::abs(v) < 0.005 ? 0.0 : v; }

std::string face_name(const TruthFace& f) {
  return f.pieces > 1 ? f.name + " #" + std::to_string(f.piece + 1) : f.name;
}

std::string maxima(const SegmentScores& s) {
  if (!s.max_normal_error_deg) return "no face has a segment";
  return "normal " + fixed("%.2f deg", *s.max_normal_error_deg) + ", offset " +
         fixed("%.1f mm", 1000.0 * *s.max_offset_error_m) + ", slope " + fixed("%.2f deg", *s.max_slope_error_deg);
}

}  // namespace

void add_segment_scores_json(const SegmentScores& s, nlohmann::ordered_json& out) {
  Json faces = Json::array();
  for (const FaceScore& f : s.faces) {
    Json j;
    j["mesh"] = f.face.name;
    j["element"] = f.face.element ? Json(*f.face.element) : Json(nullptr);
    j["piece"] = f.face.piece;
    j["pieces"] = f.face.pieces;
    j["kind"] = face_kind_name(f.face.kind);
    j["counted"] = f.face.counted();
    j["class"] = class_info(f.face.label).name;
    j["normal"] = vec(f.face.normal);
    j["offset"] = f.face.offset;
    j["center"] = vec(f.face.center);
    j["area_m2"] = f.face.area_m2;
    j["slope_deg"] = f.face.slope_deg;
    j["seen_fraction"] = f.seen_fraction;
    j["seen"] = f.seen;
    j["segments"] = f.segments;
    if (f.errors) {
      j["segment"] = f.errors->segment;
      j["normal_error_deg"] = f.errors->normal_deg;
      j["centroid_offset_m"] = f.errors->centroid_offset_m;
      j["plane_offset_error_m"] = f.errors->plane_offset_m;
      j["slope_error_deg"] = f.errors->slope_deg;
    } else {
      j["segment"] = nullptr;
    }
    faces.push_back(std::move(j));
  }
  Json j;
  j["faces"] = std::move(faces);
  j["segment_count"] = s.segment_count;
  j["counted"] = s.counted;
  j["seen"] = s.seen;
  j["matched"] = s.matched;
  j["missed"] = s.missed;
  j["split"] = s.split;
  j["on_sides"] = s.on_sides;
  j["spurious"] = s.spurious.size();
  j["spurious_ids"] = s.spurious;
  j["max_normal_error_deg"] = optional_json_number(s.max_normal_error_deg);
  j["max_offset_error_m"] = optional_json_number(s.max_offset_error_m);
  j["max_slope_error_deg"] = optional_json_number(s.max_slope_error_deg);
  out["segments"] = std::move(j);
}

std::string format_segment_scores(const SegmentScores& s) {
  std::ostringstream out;
  out << "planar segments: " << s.segment_count << " segments against " << s.counted
      << " faces (floor, wall faces, ramp decks, platform tops)\n";
  out << "  seen " << s.seen << ", matched " << s.matched << ", missed " << s.missed << ", split " << s.split
      << "; spurious " << s.spurious.size() << " (" << ids(s.spurious) << "), " << s.on_sides
      << " on side faces only\n";
  out << "  largest errors: " << maxima(s) << "\n";
  char line[200];
  std::snprintf(line, sizeof line, "  %-28s %-12s %-20s %5s  %-10s %8s %9s %9s %8s\n", "element", "face", "normal",
                "seen", "segments", "angle", "centroid", "plane", "slope");
  out << line;
  std::snprintf(line, sizeof line, "  %-28s %-12s %-20s %5s  %-10s %8s %9s %9s %8s\n", "", "", "", "", "", "deg",
                "mm", "mm", "deg");
  out << line;
  for (const FaceScore& f : s.faces) {
    if (!f.face.counted()) continue;
    const Eigen::Vector3d& n = f.face.normal;
    const std::string normal =
        fixed("(%5.2f", tidy(n.x())) + fixed(" %5.2f", tidy(n.y())) + fixed(" %5.2f)", tidy(n.z()));
    std::string errors = "       -         -         -        -";
    if (f.errors) {
      errors = fixed("%8.2f", f.errors->normal_deg) + fixed(" %+9.1f", 1000.0 * f.errors->centroid_offset_m) +
               fixed(" %+9.1f", 1000.0 * f.errors->plane_offset_m) + fixed(" %+8.2f", f.errors->slope_deg);
    }
    std::snprintf(line, sizeof line, "  %-28s %-12s %-20s %4.0f%%  %-10s %s%s\n", face_name(f.face).c_str(),
                  std::string(face_kind_name(f.face.kind)).c_str(), normal.c_str(), 100.0 * f.seen_fraction,
                  ids(f.segments).c_str(), errors.c_str(),
                  f.seen && f.segments.empty() ? "  missed" : (f.segments.size() >= 2 ? "  split" : ""));
    out << line;
  }
  return out.str();
}

std::string segment_scores_summary(const SegmentScores& s) {
  return std::to_string(s.matched) + " of " + std::to_string(s.counted) + " faces matched (" +
         std::to_string(s.seen) + " seen), missed " + std::to_string(s.missed) + ", split " +
         std::to_string(s.split) + ", spurious " + std::to_string(s.spurious.size()) + "; largest errors " +
         maxima(s);
}

}  // namespace sarmap::eval
