// Tests of TriangleScene::segments_blocked (engine/geometry/triangle_scene.hpp)
// against the exact reference of segment_box.hpp: random walls and boxes with
// random segments, then the cases a topological map's edges meet (doorways,
// walls, faces grazed or followed, endpoints inside, very long edges, bad
// coordinates), both ray modes, one and two threads.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "engine/core/error.hpp"
#include "engine/geometry/oriented_box.hpp"
#include "engine/geometry/segment_box.hpp"
#include "engine/geometry/triangle_scene.hpp"

namespace sarmap::geometry {
namespace {

constexpr RayBatchMode kModes[] = {RayBatchMode::Single, RayBatchMode::Packet16};

std::vector<ClassedMesh> closed_meshes(const std::vector<OrientedBox>& boxes) {
  std::vector<ClassedMesh> meshes;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    meshes.push_back(box_mesh(boxes[i]));
    meshes.back().label = ClassId::Wall;
    meshes.back().name = "box " + std::to_string(i);
  }
  return meshes;
}

std::vector<std::uint8_t> blocked_by(const TriangleScene& scene, const std::vector<Segment>& segments,
                                     RayBatchMode mode) {
  std::vector<std::uint8_t> blocked(segments.size(), 7);
  scene.segments_blocked(segments, blocked, mode);
  return blocked;
}

// What the exact reference says of each segment against all boxes: blocked
// when it meets some box's surface beyond the tolerance band; excluded when
// no box settles it and some box leaves it within the band.
struct Expected {
  std::vector<std::uint8_t> blocked, excluded;
  std::size_t excluded_count = 0;
  std::size_t blocked_count = 0;
  std::size_t inside_only = 0;  // solid reference blocked, surface reference not
};

Eigen::AlignedBox3d world_box(const OrientedBox& b, double margin) {
  const Eigen::Vector3d reach = b.axes.cwiseAbs() * b.half_extents + Eigen::Vector3d::Constant(margin);
  return {b.center - reach, b.center + reach};
}

Expected reference(const std::vector<OrientedBox>& boxes, const std::vector<Segment>& segments) {
  std::vector<Eigen::AlignedBox3d> bounds;
  for (const OrientedBox& b : boxes) bounds.push_back(world_box(b, 2 * kSurfaceTolerance));
  Expected e;
  e.blocked.assign(segments.size(), 0);
  e.excluded.assign(segments.size(), 0);
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const Segment& s = segments[i];
    const Eigen::AlignedBox3d sb(s.p.cwiseMin(s.q), s.p.cwiseMax(s.q));
    bool settled = false, near = false, solid = false;
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      if (!bounds[k].intersects(sb)) continue;
      solid = solid || segment_intersects_box(s, boxes[k]);
      if (segment_near_box_surface(s, boxes[k])) {
        near = true;
      } else if (segment_meets_box_surface(s, boxes[k])) {
        settled = true;
      }
    }
    e.blocked[i] = settled;
    e.excluded[i] = !settled && near;
    e.excluded_count += e.excluded[i];
    e.blocked_count += e.blocked[i];
    e.inside_only += solid && !settled && !near;
  }
  return e;
}

// Thin walls of an arena (0.1 m, 1.2 m tall, random yaw) and boxes turned
// every way, in a 20 x 20 m area.
std::vector<OrientedBox> random_boxes(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<OrientedBox> boxes;
  for (int i = 0; i < 120; ++i) {
    boxes.push_back(yawed_box({20 * u(rng), 20 * u(rng), 0.6}, {0.5 + 3.5 * u(rng), 0.1, 1.2}, 6.3 * u(rng)));
  }
  for (int i = 0; i < 30; ++i) {
    OrientedBox b;
    b.center = {20 * u(rng), 20 * u(rng), 2 * u(rng)};
    b.axes = Eigen::Quaterniond(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)
                 .normalized()
                 .toRotationMatrix();
    b.half_extents = {0.05 + 0.7 * u(rng), 0.05 + 0.7 * u(rng), 0.05 + 0.7 * u(rng)};
    boxes.push_back(b);
  }
  return boxes;
}

Eigen::Vector3d random_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
}

// Random segments, then ones made to be hard: ending exactly on a face,
// grazing a face within a micrometre, and lying wholly inside a box.
struct RandomSet {
  std::vector<Segment> segments;
  std::size_t random_count = 0;
};

RandomSet random_segments(std::mt19937_64& rng, const std::vector<OrientedBox>& boxes) {
  std::uniform_real_distribution<double> u(0, 1);
  RandomSet set;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p(-1 + 22 * u(rng), -1 + 22 * u(rng), 2 * u(rng));
    set.segments.push_back({p, p + (0.05 + 4 * u(rng)) * random_direction(rng)});
  }
  set.random_count = set.segments.size();
  for (int i = 0; i < 600; ++i) {
    const OrientedBox& b = boxes[static_cast<std::size_t>(u(rng) * static_cast<double>(boxes.size()))];
    const int axis = i % 3;
    const double side = (i / 3) % 2 ? 1.0 : -1.0;
    Eigen::Vector3d local(b.half_extents.x() * (2 * u(rng) - 1), b.half_extents.y() * (2 * u(rng) - 1),
                          b.half_extents.z() * (2 * u(rng) - 1));
    Eigen::Vector3d inside = local;
    local[axis] = side * b.half_extents[axis];
    const Eigen::Vector3d on_face = b.center + b.axes * local;
    const Eigen::Vector3d normal = side * b.axes.col(axis);
    const Eigen::Vector3d along = normal.cross(random_direction(rng)).normalized();
    if (i % 4 == 0) {
      set.segments.push_back({on_face + (0.1 + u(rng)) * (normal + along).normalized(), on_face});
    } else if (i % 4 == 1) {
      const Eigen::Vector3d c = on_face + 1e-6 * normal;
      set.segments.push_back({c - 0.5 * along, c + 0.5 * along});
    } else {
      inside *= 0.9;
      Eigen::Vector3d other =
          0.9 * Eigen::Vector3d(b.half_extents.x() * (2 * u(rng) - 1), b.half_extents.y() * (2 * u(rng) - 1),
                                b.half_extents.z() * (2 * u(rng) - 1));
      set.segments.push_back({b.center + b.axes * inside, b.center + b.axes * other});
    }
  }
  return set;
}

TEST(SegmentOcclusion, RandomBoxesMatchTheExactReferenceOutsideTheTolerance) {
  std::mt19937_64 rng(2024);
  const std::vector<OrientedBox> boxes = random_boxes(rng);
  const RandomSet set = random_segments(rng, boxes);
  const TriangleScene scene(closed_meshes(boxes));
  const Expected e = reference(boxes, set.segments);
  for (RayBatchMode mode : kModes) {
    const std::vector<std::uint8_t> got = blocked_by(scene, set.segments, mode);
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < set.segments.size(); ++i) {
      ASSERT_LE(got[i], 1) << i;
      if (e.excluded[i] || got[i] == e.blocked[i]) continue;
      if (++mismatches <= 5) {
        ADD_FAILURE() << "segment " << i << " (" << set.segments[i].p.transpose() << ") -> ("
                      << set.segments[i].q.transpose() << "): scene " << int(got[i]) << ", reference "
                      << int(e.blocked[i]);
      }
    }
    EXPECT_EQ(mismatches, 0u) << "mode " << static_cast<int>(mode);
  }
  std::size_t random_excluded = 0, random_blocked = 0;
  for (std::size_t i = 0; i < set.random_count; ++i) {
    random_excluded += e.excluded[i];
    random_blocked += e.blocked[i];
  }
  std::printf(
      "%zu random segments: %zu blocked, %zu excluded (within %g m of a surface); %zu made hard: %zu "
      "excluded, %zu inside a box only\n",
      set.random_count, random_blocked, random_excluded, kSurfaceTolerance,
      set.segments.size() - set.random_count, e.excluded_count - random_excluded, e.inside_only);
  // Random edges rarely come within 0.1 mm of a surface; the made-up hard
  // ones mostly do (ending on a face, grazing one), which shows the band
  // is applied; the segments inside a box are seen by the solid reference only.
  EXPECT_LE(random_excluded, set.random_count / 500) << random_excluded << " random segments excluded";
  EXPECT_GE(e.excluded_count - random_excluded, 200u);
  EXPECT_GE(e.inside_only, 200u);
  EXPECT_GT(random_blocked, set.random_count / 10);
  EXPECT_LT(random_blocked, set.random_count * 9 / 10);
}

TEST(SegmentOcclusion, AnswersDoNotDependOnThreadsOrRayMode) {
  std::mt19937_64 rng(7);
  const std::vector<OrientedBox> boxes = random_boxes(rng);
  const RandomSet set = random_segments(rng, boxes);
  const TriangleScene scene(closed_meshes(boxes));
  std::vector<std::uint8_t> reference_answer;
  for (int threads : {1, 2}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    for (RayBatchMode mode : kModes) {
      const std::vector<std::uint8_t> got = blocked_by(scene, set.segments, mode);
      if (reference_answer.empty()) reference_answer = got;
      EXPECT_EQ(got, reference_answer) << threads << " threads, mode " << static_cast<int>(mode);
    }
  }
}

// Two closed wall boxes along y = 0 (0.1 m thick, 1.2 m tall) with a doorway
// between x = 1 and x = 2.
std::vector<OrientedBox> corridor() {
  return {yawed_box({-1, 0, 0.6}, {4, 0.1, 1.2}, 0), yawed_box({4, 0, 0.6}, {4, 0.1, 1.2}, 0)};
}

struct Case {
  const char* what;
  Segment segment;
  bool blocked;
};

TEST(SegmentOcclusion, DoorwaysWallsFacesAndEndpoints) {
  const std::vector<OrientedBox> walls = corridor();
  const TriangleScene scene(closed_meshes(walls));
  const double tol = kSurfaceTolerance;
  const double face = 0.05;  // the walls' faces lie at y = +-0.05
  const std::vector<Case> cases = {
      {"through the doorway", {{1.5, -2, 0.3}, {1.5, 2, 0.3}}, false},
      {"slanting through the doorway", {{1.1, -1, 0.3}, {1.9, 1, 0.3}}, false},
      {"through a wall", {{0, -1, 0.3}, {0, 1, 0.3}}, true},
      {"through the other wall", {{3, -1, 0.1}, {2.5, 1, 0.5}}, true},
      {"over the walls", {{0, -1, 1.3}, {0, 1, 1.3}}, false},
      {"along a wall 1 mm from its face", {{-2, face + 1e-3, 0.3}, {5, face + 1e-3, 0.3}}, false},
      {"along a wall twice the tolerance from its face",
       {{-2, -face - 2 * tol, 0.3}, {5, -face - 2 * tol, 0.3}},
       false},
      {"ending inside a wall", {{0, -1, 0.3}, {0, 0.01, 0.3}}, true},
      {"starting inside a wall", {{4, 0.02, 0.4}, {4.5, 1, 0.4}}, true},
      {"ending twice the tolerance short of a face", {{0, -1, 0.3}, {0, -face - 2 * tol, 0.3}}, false},
      {"ending twice the tolerance past a face", {{0, -1, 0.3}, {0, -face + 2 * tol, 0.3}}, true},
      {"clipping a wall's end by 1 mm", {{0.999, -1, 0.3}, {0.999, 1, 0.3}}, true},
      {"passing a wall's end by 1 mm", {{1.001, -1, 0.3}, {1.001, 1, 0.3}}, false},
      {"10 km through the doorway", {{1.5, -5000, 0.3}, {1.5, 5000, 0.3}}, false},
      {"10 km through a wall", {{0.5, -5000, 0.3}, {0.5, 5000, 0.3}}, true},
      {"10 km along the corridor", {{-5000, 1, 0.3}, {5000, 1, 0.3}}, false},
  };
  std::vector<Segment> segments;
  for (const Case& c : cases) {
    bool hit = false, near = false;
    for (const OrientedBox& w : walls) {
      hit = hit || segment_intersects_box(c.segment, w);
      near = near || segment_near_box_surface(c.segment, w);
    }
    // Each case is clear-cut for the reference too.
    EXPECT_EQ(hit, c.blocked) << c.what;
    EXPECT_FALSE(near) << c.what;
    segments.push_back(c.segment);
  }
  for (RayBatchMode mode : kModes) {
    const std::vector<std::uint8_t> got = blocked_by(scene, segments, mode);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      EXPECT_EQ(got[i], cases[i].blocked ? 1 : 0) << cases[i].what << ", mode " << static_cast<int>(mode);
    }
  }
}

TEST(SegmentOcclusion, ZeroLengthAndWhollyInsideSegmentsAreNotBlockedBySurfaces) {
  // The scene tests surfaces, so a segment that never leaves a wall, or a
  // point, crosses none; the solid reference calls both blocked. An edge of
  // the topological map starts and ends outside walls, where both agree.
  const std::vector<OrientedBox> walls = corridor();
  const TriangleScene scene(closed_meshes(walls));
  const std::vector<Segment> segments = {
      {{0, 0, 0.3}, {0, 0, 0.3}}, {{-2, 0, 0.3}, {0, 0.01, 0.5}}, {{0, -1, 0.3}, {0, -1, 0.3}}};
  for (RayBatchMode mode : kModes) {
    EXPECT_EQ(blocked_by(scene, segments, mode), (std::vector<std::uint8_t>{0, 0, 0}));
  }
  EXPECT_TRUE(segment_intersects_box(segments[0], walls[0]));
  EXPECT_TRUE(segment_intersects_box(segments[1], walls[0]));
  EXPECT_FALSE(segment_meets_box_surface(segments[1], walls[0]));
  EXPECT_FALSE(segment_intersects_box(segments[2], walls[0]));
}

TEST(SegmentOcclusion, SegmentLyingInAFaceIsWithinTheTolerance) {
  // Exactly in a wall's face plane: the reference counts the touch as
  // blocked, and flags it as within the tolerance, so comparisons exclude
  // it; float Embree may answer either way (a ray in a triangle's plane).
  const std::vector<OrientedBox> walls = corridor();
  const Segment in_face{{-2, 0.05, 0.3}, {0, 0.05, 0.3}};
  EXPECT_TRUE(segment_intersects_box(in_face, walls[0]));
  EXPECT_TRUE(segment_near_box_surface(in_face, walls[0]));
  const TriangleScene scene(closed_meshes(walls));
  std::vector<std::uint8_t> blocked(1, 7);
  scene.segments_blocked(std::span<const Segment>(&in_face, 1), blocked);
  EXPECT_LE(blocked[0], 1);
}

// The error's code and message, or "" when nothing is thrown.
std::pair<ErrorCode, std::string> query_error(const std::vector<Segment>& segments, std::size_t flags,
                                              RayBatchMode mode) {
  const TriangleScene scene(closed_meshes(corridor()));
  std::vector<std::uint8_t> blocked(flags);
  try {
    scene.segments_blocked(segments, blocked, mode);
  } catch (const Error& e) {
    return {e.code(), e.what()};
  }
  return {ErrorCode::InvalidArgument, ""};
}

TEST(SegmentOcclusion, BadCoordinatesAreRefusedNamingTheFirstSegment) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Segment> segments(40, Segment{{0, -1, 0.3}, {0, 1, 0.3}});
  for (RayBatchMode mode : kModes) {
    auto bad = segments;
    bad[33].q.y() = nan;
    bad[17].p.x() = inf;
    auto [code, message] = query_error(bad, bad.size(), mode);
    EXPECT_EQ(code, ErrorCode::InvalidArgument);
    EXPECT_EQ(message, "TriangleScene::segments_blocked: segment 17 has a non-finite endpoint");
    bad = segments;
    bad[21].q.z() = 2e5;
    std::tie(code, message) = query_error(bad, bad.size(), mode);
    EXPECT_EQ(code, ErrorCode::OutOfRange);
    EXPECT_EQ(message, "TriangleScene::segments_blocked: segment 21 has a coordinate beyond 100000 m");
    std::tie(code, message) = query_error(segments, segments.size() - 1, mode);
    EXPECT_EQ(message, "TriangleScene::segments_blocked: 40 segments but 39 flags");
    std::tie(code, message) = query_error(segments, segments.size(), mode);
    EXPECT_EQ(message, "");
  }
}

TEST(SegmentOcclusion, EmptyBatchAndEmptyScene) {
  const TriangleScene scene(closed_meshes(corridor()));
  std::vector<std::uint8_t> none;
  scene.segments_blocked({}, none);
  const TriangleScene empty(std::vector<ClassedMesh>{});
  const std::vector<Segment> segments(3, Segment{{0, -1, 0.3}, {0, 1, 0.3}});
  for (RayBatchMode mode : kModes)
    EXPECT_EQ(blocked_by(empty, segments, mode), std::vector<std::uint8_t>(3, 0));
}

}  // namespace
}  // namespace sarmap::geometry
