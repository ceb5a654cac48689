// Segment scores on hand-made segments: the match tolerances, errors,
// missed, split and spurious counts, side faces, and the JSON and table.
#include "engine/eval/segment_scores.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>

#include "engine/core/degrees.hpp"
#include "engine/core/error.hpp"
#include "engine/eval/face_pieces.hpp"

namespace sarmap::eval {
namespace {

// A wall along y = 1 (faces at y = 0.95 and 1.05), a platform and a ramp.
sim::Arena small_arena(const std::string& extra = "") {
  return sim::parse_arena(R"({"name": "t", "bounds": {"min": [0, 0, 0], "max": [4, 4, 2]}, "floor": true,
    "elements": [
      {"type": "wall", "from": [0.5, 1], "to": [3.5, 1], "height": 1, "thickness": 0.1},
      {"type": "flat_ramp", "center": [1, 3], "size": [1, 0.8], "height": 0.3},
      {"type": "inclined_ramp", "center": [3, 3], "length": 1, "width": 0.8, "angle_deg": 15, "yaw_deg": 90})" +
                              extra + R"(],
    "trajectory": {"waypoints": [[0.5, 2], [3.5, 2]], "height": 0.5, "frames": 2, "pitch_deg": 0},
    "sensor": {"type": "depth_camera", "width": 8, "height": 6, "fx": 7, "fy": 7, "cx": 4, "cy": 3,
               "min_range": 0.1, "max_range": 6, "noise": "none"}})",
                          "t.json", ".");
}

// A segment lying exactly on the face, its rectangle the face's extent.
segments::Segment on(const TruthFace& f, std::uint32_t id, double area_scale = 1.0) {
  segments::Segment s;
  s.id = id;
  s.label = f.label;
  s.plane.normal = f.normal;
  s.plane.offset = f.offset;
  s.centroid = f.center;
  const auto [u, v] = in_plane_axes(f.normal);
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const Eigen::Vector3d& p : f.polygon) {
    const Eigen::Vector2d q((p - f.center).dot(u), (p - f.center).dot(v));
    lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  }
  const Eigen::Vector2d mid = (lo + hi) / 2;
  s.rectangle.center = f.center + mid.x() * u + mid.y() * v;
  s.rectangle.axes = {u, v};
  s.rectangle.half_extents = {(hi - lo).x() / 2, (hi - lo).y() / 2};
  s.area_m2 = f.area_m2 * area_scale;
  s.slope_deg = f.slope_deg;
  s.inliers = 1000;
  return s;
}

// Turns the segment's normal by `deg` about an in-plane axis (level when the
// face slopes), keeping its centroid.
void tilt(segments::Segment& s, double deg) {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ().cross(s.plane.normal);
  if (axis.norm() < 1e-6) axis = Eigen::Vector3d::UnitY();
  s.plane.normal = Eigen::AngleAxisd(deg * kDeg, axis.normalized()) * s.plane.normal;
  s.plane.offset = -s.plane.normal.dot(s.centroid);
  s.slope_deg = s.plane.slope_deg();
}

std::vector<double> all_seen(const std::vector<TruthFace>& faces, double fraction = 1.0) {
  return std::vector<double>(faces.size(), fraction);
}

std::size_t index_of(const std::vector<TruthFace>& faces, FaceKind kind, const Eigen::Vector3d& normal) {
  for (std::size_t i = 0; i < faces.size(); ++i) {
    if (faces[i].kind == kind && (faces[i].normal - normal).norm() < 1e-3) return i;
  }
  throw std::runtime_error("no such face");
}

TEST(SegmentScores, PerfectSegmentsMatchTheirFaces) {
  const std::vector<TruthFace> faces = truth_faces(small_arena());
  std::vector<segments::Segment> segs;
  std::uint32_t id = 0;
  for (const TruthFace& f : faces) {
    if (f.counted()) segs.push_back(on(f, id++));
  }
  const SegmentScores s = score_segments(faces, all_seen(faces), segs);
  EXPECT_EQ(s.segment_count, segs.size());
  EXPECT_EQ(s.counted, 5u);  // floor, two wall faces, platform top, ramp deck
  EXPECT_EQ(s.counted, segs.size());
  EXPECT_EQ(s.seen, 5u);
  EXPECT_EQ(s.matched, 5u);
  EXPECT_EQ(s.missed, 0u);
  EXPECT_EQ(s.split, 0u);
  EXPECT_EQ(s.on_sides, 0u);
  EXPECT_TRUE(s.spurious.empty());
  ASSERT_TRUE(s.max_normal_error_deg.has_value());
  EXPECT_NEAR(*s.max_normal_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(*s.max_offset_error_m, 0.0, 1e-9);
  EXPECT_NEAR(*s.max_slope_error_deg, 0.0, 1e-6);
  for (const FaceScore& f : s.faces) {
    if (f.face.counted()) {
      EXPECT_EQ(f.segments.size(), 1u) << f.face.name;
    }
  }
}

TEST(SegmentScores, ErrorsOfTheLargestSegment) {
  const std::vector<TruthFace> faces = truth_faces(small_arena());
  std::size_t ramp = faces.size();
  for (std::size_t i = 0; i < faces.size(); ++i) {
    if (faces[i].kind == FaceKind::RampDeck) ramp = i;
  }
  ASSERT_LT(ramp, faces.size());
  segments::Segment big = on(faces[ramp], 7);
  tilt(big, 1.5);
  big.centroid += 0.007 * faces[ramp].normal;
  big.plane.offset = -big.plane.normal.dot(big.centroid);
  segments::Segment small = on(faces[ramp], 3, 0.2);
  const std::vector<segments::Segment> segs{small, big};
  const SegmentScores s = score_segments(faces, all_seen(faces), segs);
  const FaceScore& f = s.faces[ramp];
  ASSERT_EQ(f.segments.size(), 2u);
  EXPECT_EQ(f.segments[0], 7u);  // largest first
  EXPECT_EQ(s.split, 1u);
  ASSERT_TRUE(f.errors.has_value());
  EXPECT_EQ(f.errors->segment, 7u);
  EXPECT_NEAR(f.errors->normal_deg, 1.5, 1e-6);
  EXPECT_NEAR(f.errors->centroid_offset_m, 0.007, 1e-9);
  EXPECT_NEAR(std::abs(f.errors->slope_deg), 1.5, 1e-6);  // tilted about the level axis
  EXPECT_NEAR(*s.max_normal_error_deg, 1.5, 1e-6);
  EXPECT_NEAR(*s.max_offset_error_m, 0.007, 1e-9);
  // The floor and the others have no segment: seen, so missed.
  EXPECT_EQ(s.matched, 1u);
  EXPECT_EQ(s.missed, 4u);
}

TEST(SegmentScores, MatchTolerances) {
  const std::vector<TruthFace> faces = truth_faces(small_arena());
  const std::size_t wall = index_of(faces, FaceKind::WallFace, Eigen::Vector3d::UnitY());
  const TruthFace& f = faces[wall];
  const auto matches = [&](const segments::Segment& s) { return segment_matches_face(s, f); };
  EXPECT_TRUE(matches(on(f, 0)));
  segments::Segment s = on(f, 0);
  tilt(s, kMatchNormalDeg - 0.5);
  EXPECT_TRUE(matches(s));
  s = on(f, 0);
  tilt(s, kMatchNormalDeg + 0.5);
  EXPECT_FALSE(matches(s));
  s = on(f, 0);
  s.plane.normal = -s.plane.normal;  // oriented: the other side of the wall
  EXPECT_FALSE(matches(s));
  s = on(f, 0);
  s.centroid += (kMatchOffset - 0.01) * f.normal;
  EXPECT_TRUE(matches(s));
  s.centroid += 0.02 * f.normal;
  EXPECT_FALSE(matches(s));
  s = on(f, 0);
  s.label = ClassId::FlatRamp;
  EXPECT_FALSE(matches(s));
  // A small segment beyond the face's end: within the margin, then not.
  s = on(f, 0);
  s.rectangle.half_extents = {0.05, 0.05};
  s.centroid = s.rectangle.center = Eigen::Vector3d(3.55 + kMatchMargin - 0.02, 1.05, 0.5);
  EXPECT_TRUE(matches(s));
  s.centroid = s.rectangle.center = Eigen::Vector3d(3.55 + kMatchMargin + 0.05, 1.05, 0.5);
  EXPECT_FALSE(matches(s));
  // A long segment whose centroid lies off the face still matches when it covers the face's centre.
  s.rectangle.half_extents = {5, 0.5};
  EXPECT_TRUE(matches(s));
}

TEST(SegmentScores, SidesSpuriousAndUnseen) {
  const std::vector<TruthFace> faces = truth_faces(small_arena());
  std::vector<double> seen = all_seen(faces, 0.0);
  const std::size_t top = index_of(faces, FaceKind::PlatformTop, Eigen::Vector3d::UnitZ());
  const std::size_t wall = index_of(faces, FaceKind::WallFace, Eigen::Vector3d::UnitY());
  seen[top] = 0.6;
  seen[wall] = 0.4;  // under half: not seen, so not missed
  std::size_t side = faces.size();
  for (std::size_t i = 0; i < faces.size(); ++i) {
    if (faces[i].kind == FaceKind::Side && faces[i].label == ClassId::FlatRamp) side = i;
  }
  ASSERT_LT(side, faces.size());
  segments::Segment on_side = on(faces[side], 1);
  segments::Segment stray = on(faces[top], 2);
  stray.centroid.z() += 0.2;  // floating above the platform
  segments::Segment wrong_class = on(faces[top], 3);
  wrong_class.label = ClassId::Terrain;
  const SegmentScores s = score_segments(faces, seen, std::vector<segments::Segment>{on_side, stray, wrong_class});
  EXPECT_EQ(s.seen, 1u);
  EXPECT_EQ(s.missed, 1u);  // the platform top
  EXPECT_EQ(s.matched, 0u);
  EXPECT_EQ(s.on_sides, 1u);
  EXPECT_EQ(s.spurious, (std::vector<std::uint32_t>{2, 3}));
  EXPECT_FALSE(s.max_normal_error_deg.has_value());
  EXPECT_EQ(s.faces[side].segments, std::vector<std::uint32_t>{1});
  EXPECT_THROW(score_segments(faces, {}, std::vector<segments::Segment>{}), Error);
}

TEST(SegmentScores, OneSegmentAcrossTwoPiecesMatchesBoth) {
  // A wall standing against the +y face splits it in two.
  const std::vector<TruthFace> faces = truth_faces(
      small_arena(R"(, {"type": "wall", "from": [2, 1], "to": [2, 2], "height": 1, "thickness": 0.1})"));
  std::vector<std::size_t> pieces;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    if (faces[i].element == 0u && faces[i].kind == FaceKind::WallFace && faces[i].normal.y() > 0.5) {
      pieces.push_back(i);
    }
  }
  ASSERT_EQ(pieces.size(), 2u);
  // The whole face as one segment.
  TruthFace whole = faces[pieces[0]];
  whole.polygon = {{0.45, 1.05, 0}, {3.55, 1.05, 0}, {3.55, 1.05, 1}, {0.45, 1.05, 1}};
  whole.center = {2.0, 1.05, 0.5};
  const SegmentScores s = score_segments(faces, all_seen(faces), std::vector<segments::Segment>{on(whole, 4)});
  EXPECT_EQ(s.faces[pieces[0]].segments, std::vector<std::uint32_t>{4});
  EXPECT_EQ(s.faces[pieces[1]].segments, std::vector<std::uint32_t>{4});
  EXPECT_EQ(s.split, 0u);
}

TEST(SegmentScores, JsonAndTable) {
  const std::vector<TruthFace> faces = truth_faces(small_arena());
  const std::size_t top = index_of(faces, FaceKind::PlatformTop, Eigen::Vector3d::UnitZ());
  const std::size_t wall = index_of(faces, FaceKind::WallFace, Eigen::Vector3d::UnitY());
  const SegmentScores s =
      score_segments(faces, all_seen(faces), std::vector<segments::Segment>{on(faces[top], 5), on(faces[top], 6, 0.5)});
  nlohmann::ordered_json j;
  add_segment_scores_json(s, j);
  const auto& seg = j.at("segments");
  EXPECT_EQ(seg.at("faces").size(), faces.size());
  EXPECT_EQ(seg.at("seen").get<int>(), 5);
  EXPECT_EQ(seg.at("matched").get<int>(), 1);
  EXPECT_EQ(seg.at("missed").get<int>(), 4);
  EXPECT_EQ(seg.at("split").get<int>(), 1);
  EXPECT_EQ(seg.at("spurious").get<int>(), 0);
  EXPECT_DOUBLE_EQ(seg.at("max_normal_error_deg").get<double>(), 0.0);
  EXPECT_TRUE(seg.contains("max_offset_error_m"));
  EXPECT_TRUE(seg.contains("max_slope_error_deg"));
  const auto& face = seg.at("faces").at(top);
  EXPECT_EQ(face.at("kind").get<std::string>(), "platform_top");
  EXPECT_EQ(face.at("class").get<std::string>(), "flat_ramp");
  EXPECT_EQ(face.at("segment").get<int>(), 5);
  EXPECT_EQ(face.at("segments"), nlohmann::json::array({5, 6}));
  EXPECT_TRUE(seg.at("faces").at(wall).at("segment").is_null());

  const std::string table = format_segment_scores(s);
  EXPECT_NE(table.find("missed 4, split 1"), std::string::npos) << table;
  EXPECT_NE(table.find("5 6"), std::string::npos) << table;
  EXPECT_NE(table.find("split\n"), std::string::npos) << table;
  EXPECT_NE(table.find("missed\n"), std::string::npos) << table;
  const std::string line = segment_scores_summary(s);
  EXPECT_NE(line.find("1 of 5 faces matched"), std::string::npos) << line;
  EXPECT_EQ(line.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace sarmap::eval
