// Arena-level tests of the segment stage against the arenas' true faces:
// every seen wall face, ramp deck and platform top of the default arena is one
// segment with its plane within 2 degrees and 1 cm and ramp slopes within 1
// degree; a wall with a doorway is two segments; a platform never merges with
// the floor. Under the sanitizers only the doorway arena runs: the rest are
// accuracy cases on the whole default arena.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/sim/arena.hpp"
#include "tests/eval/segmented_arena.hpp"
#include "tests/release_only.hpp"

namespace sarmap::eval {
namespace {

using testing::segment_arena;
using testing::SegmentedArena;

// A 5 x 4 m room split by a wall along y = 2 with a 0.7 m doorway (x 2.05 to
// 2.75), a 0.25 m platform in the south half, and a drive that looks at both
// sides of the doorway wall from within the segment stage's range, and at the
// platform from the floor.
sim::Arena doorway_arena() {
  return sim::parse_arena(R"({
    "name": "doorway-5x4",
    "bounds": {"min": [0, 0, 0], "max": [5, 4, 2.4]},
    "floor": true,
    "elements": [
      {"type": "wall", "from": [0, 0], "to": [5, 0], "height": 1.0, "thickness": 0.1},
      {"type": "wall", "from": [5, 0], "to": [5, 4], "height": 1.0, "thickness": 0.1},
      {"type": "wall", "from": [5, 4], "to": [0, 4], "height": 1.0, "thickness": 0.1},
      {"type": "wall", "from": [0, 4], "to": [0, 0], "height": 1.0, "thickness": 0.1},
      {"type": "wall", "from": [0, 2], "to": [2, 2], "height": 1.0, "thickness": 0.1},
      {"type": "wall", "from": [2.8, 2], "to": [5, 2], "height": 1.0, "thickness": 0.1},
      {"type": "flat_ramp", "center": [3.8, 0.9], "size": [1.0, 0.8], "height": 0.25, "yaw_deg": 0}
    ],
    "trajectory": {"waypoints": [[1.6, 0.3], [0.6, 1.0], [1.0, 0.4], [2.0, 1.1], [3.0, 0.3], [4.6, 0.3],
                                 [4.7, 1.4], [2.4, 1.3], [2.4, 3.3], [4.5, 3.5], [4.4, 2.6], [3.6, 3.6],
                                 [3.3, 2.6], [1.0, 3.6], [1.2, 2.6]],
                   "height": 0.5, "frames": 120, "pitch_deg": -15},
    "sensor": {"type": "depth_camera", "width": 320, "height": 240, "fx": 277, "fy": 277, "cx": 160, "cy": 120,
               "min_range": 0.3, "max_range": 5.0, "noise": "kinect"}
  })",
                          "doorway-5x4", ".");
}

// Every frame, as `sarmap run` takes them.
const SegmentedArena& default_arena() {
  static const SegmentedArena a =
      segment_arena(sim::load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json"), 1);
  return a;
}

const SegmentedArena& doorway() {
  static const SegmentedArena a = segment_arena(doorway_arena(), 1);
  return a;
}

const segments::Segment& segment(const SegmentedArena& a, std::uint32_t id) {
  for (const segments::Segment& s : a.segments) {
    if (s.id == id) return s;
  }
  throw std::runtime_error("no segment " + std::to_string(id));
}

std::string describe(const FaceScore& f) {
  char text[200];
  std::snprintf(text, sizeof text, "%s %s normal (%.2f %.2f %.2f), seen %.0f%%", f.face.name.c_str(),
                std::string(face_kind_name(f.face.kind)).c_str(), f.face.normal.x(), f.face.normal.y(),
                f.face.normal.z(), 100 * f.seen_fraction);
  return text;
}

TEST(SegmentArena, DefaultArenaSeenFacesAreOneSegmentEach) {
  RELEASE_ONLY();
  const SegmentedArena& a = default_arena();
  SCOPED_TRACE(format_segment_scores(a.scores));
  std::size_t checked = 0;
  for (const FaceScore& f : a.scores.faces) {
    if (f.face.kind == FaceKind::Floor || !f.face.counted() || !f.seen) continue;
    ++checked;
    EXPECT_EQ(f.segments.size(), 1u) << describe(f);
  }
  // Four inner wall faces, two ramp decks, one platform top.
  EXPECT_EQ(checked, 7u);
}

TEST(SegmentArena, DefaultArenaPlanesMatchTheTrueSurfaces) {
  RELEASE_ONLY();
  const SegmentedArena& a = default_arena();
  SCOPED_TRACE(format_segment_scores(a.scores));
  for (const FaceScore& f : a.scores.faces) {
    if (!f.face.counted() || !f.seen || !f.errors) continue;
    const segments::Segment& s = segment(a, f.errors->segment);
    EXPECT_LE(f.errors->normal_deg, 2.0) << describe(f);
    EXPECT_LE(std::abs(f.errors->centroid_offset_m), 0.01) << describe(f);
    // The plane itself, where the face is, not only at the segment's centroid.
    EXPECT_LE(std::abs(s.plane.distance(f.face.center)), 0.01) << describe(f);
    if (f.face.kind == FaceKind::RampDeck) {
      EXPECT_LE(std::abs(f.errors->slope_deg), 1.0) << describe(f);
    }
  }
}

TEST(SegmentArena, DefaultArenaHasNoSpuriousSegments) {
  RELEASE_ONLY();
  const SegmentedArena& a = default_arena();
  SCOPED_TRACE(format_segment_scores(a.scores));
  EXPECT_TRUE(a.scores.spurious.empty());
  EXPECT_EQ(a.scores.missed, 0u);
}

TEST(SegmentArena, DoorwayWallIsTwoSegments) {
  const SegmentedArena& a = doorway();
  SCOPED_TRACE(format_segment_scores(a.scores));
  // Per side of the doorway wall (elements 4 and 5), the ids of the segments
  // on each piece's face.
  for (const double side : {-1.0, 1.0}) {
    std::vector<std::uint32_t> ids;
    for (const FaceScore& f : a.scores.faces) {
      if (f.face.kind != FaceKind::WallFace || !f.face.element || *f.face.element < 4) continue;
      if (f.face.normal.y() * side < 0.5) continue;
      ASSERT_TRUE(f.seen) << describe(f);
      ASSERT_EQ(f.segments.size(), 1u) << describe(f);
      ids.push_back(f.segments.front());
    }
    ASSERT_EQ(ids.size(), 2u);
    EXPECT_NE(ids[0], ids[1]) << "one segment spans the doorway on side " << side;
    // No wall segment reaches into the doorway.
    const Eigen::Vector3d doorway(2.4, 2.0 + 0.05 * side, 0.5);
    for (const segments::Segment& s : a.segments) {
      if (s.label != ClassId::Wall) continue;
      EXPECT_FALSE(std::abs(s.plane.distance(doorway)) < 0.05 && s.covers(doorway, 0.0))
          << "segment " << s.id << " covers the doorway";
    }
  }
}

// The platform's top and the floor are different classes with the labels
// classifier, so only a class-blind merge could join them: every point of the
// platform's segment lies on its top and no floor segment holds a point of it.
void expect_platform_apart_from_floor(const SegmentedArena& a, const sim::FlatRampSpec& p) {
  const auto on_platform = [&](const Eigen::Vector3f& q) {
    return std::abs(q.x() - p.center.x()) < p.size.x() / 2 + 0.1 &&
           std::abs(q.y() - p.center.y()) < p.size.y() / 2 + 0.1;
  };
  std::size_t top_segments = 0;
  for (const FaceScore& f : a.scores.faces) {
    if (f.face.kind != FaceKind::PlatformTop) continue;
    ASSERT_TRUE(f.seen) << describe(f);
    ASSERT_EQ(f.segments.size(), 1u) << describe(f);
    ++top_segments;
    std::size_t off_top = 0;
    for (const Eigen::Vector3f& q : a.map.member_points(f.segments.front())) {
      if (!on_platform(q) || std::abs(q.z() - p.height) > 0.05) {
        ++off_top;
        ADD_FAILURE() << "platform segment point " << q.transpose();
      }
    }
    EXPECT_EQ(off_top, 0u) << "points of the platform's segment " << f.segments.front() << " off its top";
  }
  EXPECT_EQ(top_segments, 1u);
  std::size_t floor_points = 0;
  for (const segments::Segment& s : a.segments) {
    if (s.label != ClassId::Terrain) continue;
    std::size_t off_floor = 0;
    for (const Eigen::Vector3f& q : a.map.member_points(s.id)) {
      ++floor_points;
      off_floor += std::abs(q.z()) > 0.05;
    }
    EXPECT_EQ(off_floor, 0u) << "points of floor segment " << s.id << " off the floor";
  }
  EXPECT_GT(floor_points, 1000u);
}

TEST(SegmentArena, PlatformAndFloorStayApart) {
  RELEASE_ONLY();
  {
    SCOPED_TRACE("doorway arena");
    const sim::Arena arena = doorway_arena();
    expect_platform_apart_from_floor(doorway(), std::get<sim::FlatRampSpec>(arena.elements[6].shape));
  }
  {
    SCOPED_TRACE("default arena");
    const sim::Arena arena = sim::load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
    expect_platform_apart_from_floor(default_arena(), std::get<sim::FlatRampSpec>(arena.elements[6].shape));
  }
}

}  // namespace
}  // namespace sarmap::eval
