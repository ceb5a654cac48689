#include "engine/eval/segment_scores.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/core/error.hpp"

namespace sarmap::eval {
namespace {

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  // atan2 of |a x b| and a . b stays exact for tiny angles, where acos does not.
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / std::numbers::pi;
}

FaceErrors errors_of(const segments::Segment& s, const TruthFace& f) {
  FaceErrors e;
  e.segment = s.id;
  e.normal_deg = angle_deg(s.plane.normal, f.normal);
  e.centroid_offset_m = f.distance(s.centroid);
  e.plane_offset_m = s.plane.offset - f.offset;
  e.slope_deg = s.slope_deg - f.slope_deg;
  return e;
}

void keep_max(std::optional<double>& m, double v) { m = m ? std::max(*m, std::abs(v)) : std::abs(v); }

}  // namespace

bool segment_matches_face(const segments::Segment& s, const TruthFace& f) {
  if (s.label != f.label) return false;
  if (!(angle_deg(s.plane.normal, f.normal) <= kMatchNormalDeg)) return false;
  if (!(std::abs(f.distance(s.centroid)) <= kMatchOffset)) return false;
  return f.contains(s.centroid, kMatchMargin) || s.covers(f.center, kMatchMargin);
}

SegmentScores score_segments(const std::vector<TruthFace>& faces, const std::vector<double>& seen_fractions,
                             std::span<const segments::Segment> segments) {
  if (seen_fractions.size() != faces.size()) {
    throw Error(ErrorCode::InvalidArgument, "score_segments: one seen fraction per face is needed");
  }
  SegmentScores out;
  out.segment_count = segments.size();
  // Largest first, so each face's first match is its largest segment.
  std::vector<const segments::Segment*> by_size;
  for (const segments::Segment& s : segments) by_size.push_back(&s);
  std::stable_sort(by_size.begin(), by_size.end(), [](const segments::Segment* a, const segments::Segment* b) {
    return a->area_m2 != b->area_m2 ? a->area_m2 > b->area_m2 : a->inliers > b->inliers;
  });
  std::vector<bool> any_match(by_size.size(), false), counted_match(by_size.size(), false);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    FaceScore fs;
    fs.face = faces[i];
    fs.seen_fraction = seen_fractions[i];
    fs.seen = seen_fractions[i] >= kSeenFraction;
    for (std::size_t k = 0; k < by_size.size(); ++k) {
      if (!segment_matches_face(*by_size[k], fs.face)) continue;
      fs.segments.push_back(by_size[k]->id);
      any_match[k] = true;
      if (fs.face.counted()) counted_match[k] = true;
    }
    if (!fs.segments.empty()) {
      const auto largest = std::find_if(by_size.begin(), by_size.end(), [&](const segments::Segment* s) {
        return s->id == fs.segments.front();
      });
      fs.errors = errors_of(**largest, fs.face);
    }
    if (fs.face.counted()) {
      ++out.counted;
      out.seen += fs.seen;
      out.matched += !fs.segments.empty();
      out.missed += fs.seen && fs.segments.empty();
      out.split += fs.segments.size() >= 2;
      if (fs.errors) {
        keep_max(out.max_normal_error_deg, fs.errors->normal_deg);
        keep_max(out.max_offset_error_m, fs.errors->centroid_offset_m);
        keep_max(out.max_slope_error_deg, fs.errors->slope_deg);
      }
    }
    out.faces.push_back(std::move(fs));
  }
  for (std::size_t k = 0; k < by_size.size(); ++k) {
    if (!any_match[k]) out.spurious.push_back(by_size[k]->id);
    out.on_sides += any_match[k] && !counted_match[k];
  }
  std::sort(out.spurious.begin(), out.spurious.end());
  return out;
}

SegmentScores score_segments(const sim::Arena& arena, const sim::GroundTruthGrid& truth,
                             std::span<const segments::Segment> segments) {
  const std::vector<TruthFace> faces = truth_faces(arena);
  std::vector<double> seen;
  seen.reserve(faces.size());
  for (const TruthFace& f : faces) seen.push_back(seen_fraction(f, truth));
  return score_segments(faces, seen, segments);
}

}  // namespace sarmap::eval
