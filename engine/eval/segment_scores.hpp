// Scores a run's planar segments (segments.json) against the arena's true
// faces: which segment matches each wall face, ramp deck, platform top and the
// floor, how far off its plane is, and the faces missed or split and the
// segments that match nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "engine/eval/truth_surfaces.hpp"
#include "engine/segments/segment.hpp"

namespace sarmap::eval {

// A segment matches a face of its own class when their (oriented) normals
// agree within kMatchNormalDeg, the segment's centroid lies within
// kMatchOffset of the face's plane, and either the centroid projected onto the
// plane lies on the face grown by kMatchMargin, or the face's centre lies on
// the segment's rectangle grown by kMatchMargin (one segment spanning two
// collinear wall elements matches both). The tolerances are loose next to the
// errors a map should have: they decide which face a segment belongs to, the
// errors below say how well it fits.
inline constexpr double kMatchNormalDeg = 10.0;
inline constexpr double kMatchOffset = 0.05;  // metres
inline constexpr double kMatchMargin = 0.10;  // metres
// A face counts as seen when at least this fraction of it was (seen_fraction).
inline constexpr double kSeenFraction = 0.5;

bool segment_matches_face(const segments::Segment& segment, const TruthFace& face);

// How far a face's largest matching segment is from it.
struct FaceErrors {
  std::uint32_t segment = 0;     // its id
  double normal_deg = 0;         // angle between the normals
  double centroid_offset_m = 0;  // signed distance of its centroid from the face's plane
  double plane_offset_m = 0;     // its plane's offset minus the face's
  double slope_deg = 0;          // its slope minus the face's
};

struct FaceScore {
  TruthFace face;
  double seen_fraction = 0;
  bool seen = false;
  std::vector<std::uint32_t> segments;  // ids of the matching segments, largest (by area) first
  std::optional<FaceErrors> errors;     // of segments.front()
};

struct SegmentScores {
  std::size_t segment_count = 0;
  std::vector<FaceScore> faces;  // every truth face, sides included, in mesh order
  // Over the counted faces (the floor, wall faces, ramp decks, platform tops).
  std::size_t counted = 0;
  std::size_t seen = 0;
  std::size_t matched = 0;  // with at least one segment, seen or not
  std::size_t missed = 0;   // seen, with no segment
  std::size_t split = 0;    // with two or more segments
  // Segments matching a side face and no counted face.
  std::size_t on_sides = 0;
  // Ids of the segments matching no face at all.
  std::vector<std::uint32_t> spurious;
  // Largest absolute errors over the counted faces that have a segment;
  // none when no face has one. The offset is the centroid's.
  std::optional<double> max_normal_error_deg, max_offset_error_m, max_slope_error_deg;
};

// Scores segments against faces whose seen fractions are given (one per face).
SegmentScores score_segments(const std::vector<TruthFace>& faces, const std::vector<double>& seen_fractions,
                             std::span<const segments::Segment> segments);
// The same against the arena's faces, seen as the truth grid says.
SegmentScores score_segments(const sim::Arena& arena, const sim::GroundTruthGrid& truth,
                             std::span<const segments::Segment> segments);

// The figures under "segments" in `out`: faces (every face with its kind,
// class, normal, offset, area, seen fraction, matching segment ids and errors),
// segment_count, counted, seen, matched, missed, split, on_sides, spurious,
// max_normal_error_deg, max_offset_error_m, max_slope_error_deg.
void add_segment_scores_json(const SegmentScores& scores, nlohmann::ordered_json& out);
// Totals, then one line per counted face, for `sarmap eval`.
std::string format_segment_scores(const SegmentScores& scores);
// One line of totals and largest errors, for `sarmap demo`.
std::string segment_scores_summary(const SegmentScores& scores);

}  // namespace sarmap::eval
