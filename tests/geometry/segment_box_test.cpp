// Tests of engine/geometry/segment_box.hpp, the exact reference: hand-worked
// cases (crossing, touching, missing, inside, zero length) and, on random
// boxes and segments, agreement between the slab test, the signed distances
// and a dense sampling of the segment.
#include "engine/geometry/segment_box.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <Eigen/Geometry>

#include "engine/core/error.hpp"

namespace sarmap::geometry {
namespace {

// The cube [-1, 1]^3 turned by 30 degrees about z and moved to (5, 5, 1), so
// the tests also exercise the change of frame; cases that touch a face
// exactly use it unturned, where the change of frame is exact in binary.
OrientedBox cube() { return yawed_box({5, 5, 1}, {2, 2, 2}, std::numbers::pi / 6); }
OrientedBox aligned_cube() { return {{5, 5, 1}, Eigen::Matrix3d::Identity(), {1, 1, 1}}; }

// A point given in the cube's own frame.
Eigen::Vector3d at(double x, double y, double z) {
  const OrientedBox b = cube();
  return b.center + b.axes * Eigen::Vector3d(x, y, z);
}
Eigen::Vector3d aligned_at(double x, double y, double z) {
  return aligned_cube().center + Eigen::Vector3d(x, y, z);
}

Segment seg(const Eigen::Vector3d& p, const Eigen::Vector3d& q) { return {p, q}; }

TEST(SegmentBox, CrossingTouchingAndMissing) {
  const OrientedBox b = cube();
  EXPECT_TRUE(segment_intersects_box(seg(at(-3, 0, 0), at(3, 0, 0)), b));
  EXPECT_FALSE(segment_intersects_box(seg(at(-3, 0, 0), at(-1.001, 0, 0)), b));
  EXPECT_FALSE(segment_intersects_box(seg(at(0, 2.001, 0), at(2.001, 0, 0)), b));
  // Parallel to a face, 1 mm outside it.
  EXPECT_FALSE(segment_intersects_box(seg(at(-3, 1.001, 0), at(3, 1.001, 0)), b));
  // One end inside, both ends inside.
  EXPECT_TRUE(segment_intersects_box(seg(at(0.5, 0.5, 0.5), at(3, 3, 3)), b));
  EXPECT_TRUE(segment_intersects_box(seg(at(0.5, 0.5, 0.5), at(-0.5, 0.2, 0.1)), b));
  // Touching counts: ending on a face, passing a corner edge, lying in a face.
  const OrientedBox a = aligned_cube();
  EXPECT_TRUE(segment_intersects_box(seg(aligned_at(-3, 0, 0), aligned_at(-1, 0, 0)), a));
  EXPECT_TRUE(segment_intersects_box(seg(aligned_at(0, 2, 0.5), aligned_at(2, 0, 0.5)), a));
  EXPECT_TRUE(segment_intersects_box(seg(aligned_at(-3, 1, 0), aligned_at(3, 1, 0)), a));
  EXPECT_TRUE(segment_intersects_box(seg(aligned_at(1, 1, 1), aligned_at(3, 3, 3)), a));
  EXPECT_FALSE(segment_intersects_box(seg(aligned_at(1, 1, 1.5), aligned_at(3, 3, 3)), a));
}

TEST(SegmentBox, ZeroLengthSegmentIsPointInBox) {
  const OrientedBox b = cube();
  EXPECT_TRUE(segment_intersects_box(seg(at(0.3, -0.9, 0.2), at(0.3, -0.9, 0.2)), b));
  EXPECT_FALSE(segment_intersects_box(seg(at(1.01, 0, 0), at(1.01, 0, 0)), b));
  EXPECT_TRUE(segment_intersects_box(seg(aligned_at(1, 0, 0), aligned_at(1, 0, 0)), aligned_cube()));
  EXPECT_NEAR(segment_box_signed_distance(seg(at(0.3, -0.9, 0.2), at(0.3, -0.9, 0.2)), b), -0.1, 1e-12);
  EXPECT_NEAR(segment_box_signed_distance(seg(at(4, 5, 1), at(4, 5, 1)), b), std::sqrt(9.0 + 16.0), 1e-12);
}

TEST(SegmentBox, SurfaceIsMetUnlessTheSegmentLiesInside) {
  const OrientedBox b = cube();
  EXPECT_TRUE(segment_meets_box_surface(seg(at(0, 0, 0), at(3, 0, 0)), b));
  EXPECT_FALSE(segment_meets_box_surface(seg(at(-0.5, 0, 0), at(0.5, 0, 0)), b));
  EXPECT_FALSE(segment_meets_box_surface(seg(at(-3, 2, 0), at(3, 2, 0)), b));
  // Inside and ending on a face touches the surface.
  EXPECT_TRUE(segment_meets_box_surface(seg(aligned_at(0, 0, 0), aligned_at(1, 0, 0)), aligned_cube()));
}

TEST(SegmentBox, SignedDistancesOfPoints) {
  const OrientedBox b = cube();
  EXPECT_NEAR(signed_distance(at(1.3, 0, 0), b), 0.3, 1e-12);
  EXPECT_NEAR(signed_distance(at(2, 3, -1), b), std::sqrt(1.0 + 4.0), 1e-12);
  EXPECT_NEAR(signed_distance(at(0.2, -0.7, 0.1), b), -0.3, 1e-12);
  EXPECT_NEAR(signed_distance(at(0, 1, 0), b), 0.0, 1e-12);
}

TEST(SegmentBox, SignedDistancesOfSegments) {
  const OrientedBox b = cube();
  // Passes 0.25 above the top face, over its whole length.
  EXPECT_NEAR(segment_box_signed_distance(seg(at(-3, 0, 1.25), at(3, 0.5, 1.25)), b), 0.25, 1e-12);
  // Skew past the edge x = y = 1: the nearest point is (1.5, 1.5, 0), at
  // sqrt(0.5) from the edge.
  EXPECT_NEAR(segment_box_signed_distance(seg(at(0, 3, 0), at(3, 0, 0)), b), std::sqrt(0.5), 1e-12);
  // Through the middle: reaches a full half extent deep.
  EXPECT_NEAR(segment_box_signed_distance(seg(at(-3, 0, 0), at(3, 0, 0)), b), -1.0, 1e-12);
  // Cuts a corner: deepest at x = y = 0.9, 0.1 inside both faces.
  EXPECT_NEAR(segment_box_signed_distance(seg(at(0.8, 1.0, 0), at(1.0, 0.8, 0)), b), -0.1, 1e-12);
  // Misses that corner along x + y = 2.7: nearest at (1.35, 1.35, 0).
  EXPECT_NEAR(segment_box_signed_distance(seg(at(-0.3, 3, 0), at(3, -0.3, 0)), b), 0.35 * std::sqrt(2.0),
              1e-12);
}

TEST(SegmentBox, NearSurfaceFlagsTheAmbiguousCases) {
  const OrientedBox b = cube();
  const double tol = kSurfaceTolerance;
  // Ends within the tolerance of a face, either side.
  EXPECT_TRUE(segment_near_box_surface(seg(at(-3, 0, 0), at(-1 - tol / 2, 0, 0)), b));
  EXPECT_TRUE(segment_near_box_surface(seg(at(0, 0, 0), at(1 - tol / 2, 0, 0)), b));
  // Grazes an edge, or runs along a face.
  EXPECT_TRUE(segment_near_box_surface(seg(at(0, 2 + tol / 4, 0), at(2, tol / 4, 0)), b));
  EXPECT_TRUE(segment_near_box_surface(seg(at(-3, 1, 0), at(3, 1, 0)), b));
  // Clearly through, clearly past, clearly inside, twice the tolerance away.
  EXPECT_FALSE(segment_near_box_surface(seg(at(-3, 0, 0), at(3, 0, 0)), b));
  EXPECT_FALSE(segment_near_box_surface(seg(at(-3, 1.5, 0), at(3, 1.5, 0)), b));
  EXPECT_FALSE(segment_near_box_surface(seg(at(-0.5, 0, 0), at(0.5, 0, 0)), b));
  EXPECT_FALSE(segment_near_box_surface(seg(at(-3, 0, 0), at(-1 - 2 * tol, 0, 0)), b));
  EXPECT_FALSE(segment_near_box_surface(seg(at(-3, 0, 0), at(-1 + 2 * tol, 0, 0)), b));
}

TEST(SegmentBox, NonFiniteEndpointsAreRefused) {
  const OrientedBox b = cube();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(segment_intersects_box(seg({nan, 0, 0}, {1, 1, 1}), b), Error);
  EXPECT_THROW(segment_intersects_box(seg({0, 0, 0}, {1, inf, 1}), b), Error);
  EXPECT_THROW(segment_box_signed_distance(seg({0, 0, 0}, {1, 1, -inf}), b), Error);
}

// A random box of any orientation and a random segment near it.
struct RandomCase {
  OrientedBox box;
  Segment segment;
};

RandomCase random_case(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_real_distribution<double> size(0.05, 2);
  RandomCase c;
  c.box.center = {3 * u(rng), 3 * u(rng), 3 * u(rng)};
  c.box.axes = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
  c.box.half_extents = {size(rng), size(rng), size(rng)};
  c.segment.p = c.box.center + Eigen::Vector3d(3 * u(rng), 3 * u(rng), 3 * u(rng));
  c.segment.q = c.segment.p + Eigen::Vector3d(2 * u(rng), 2 * u(rng), 2 * u(rng));
  return c;
}

TEST(SegmentBox, SlabTestAgreesWithTheSignedDistance) {
  std::mt19937_64 rng(11);
  int hits = 0, misses = 0;
  for (int i = 0; i < 20000; ++i) {
    const RandomCase c = random_case(rng);
    const double d = segment_box_signed_distance(c.segment, c.box);
    if (std::abs(d) < 1e-9) continue;
    const bool hit = segment_intersects_box(c.segment, c.box);
    ASSERT_EQ(hit, d < 0) << "case " << i << " distance " << d;
    (hit ? hits : misses) += 1;
  }
  // Both answers occur often enough for the agreement to mean something.
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 1000);
}

TEST(SegmentBox, SignedDistanceIsTheMinimumOverTheSegment) {
  std::mt19937_64 rng(12);
  constexpr int kSamples = 4000;
  for (int i = 0; i < 500; ++i) {
    const RandomCase c = random_case(rng);
    const double exact = segment_box_signed_distance(c.segment, c.box);
    double sampled = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= kSamples; ++k) {
      const double t = static_cast<double>(k) / kSamples;
      sampled = std::min(sampled, signed_distance(c.segment.p + t * (c.segment.q - c.segment.p), c.box));
    }
    // No sample lies below the exact minimum, and the nearest sample is
    // within one step (the distance is 1-Lipschitz) of it.
    const double step = (c.segment.q - c.segment.p).norm() / kSamples;
    ASSERT_GE(sampled, exact - 1e-12) << "case " << i;
    ASSERT_LE(sampled, exact + step + 1e-12) << "case " << i;
  }
}

}  // namespace
}  // namespace sarmap::geometry
