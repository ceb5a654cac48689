// Tests of engine/geometry/oriented_box.hpp: corners where the box says,
// faces wound outwards, the bottom left out on request, bad boxes refused.
#include "engine/geometry/oriented_box.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "engine/core/error.hpp"

namespace sarmap::geometry {
namespace {

OrientedBox tilted_box() {
  OrientedBox b;
  b.center = {1, -2, 0.5};
  b.axes =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  b.half_extents = {1.5, 0.05, 0.6};
  return b;
}

TEST(OrientedBox, CornersFollowTheAxesAndHalfExtents) {
  const OrientedBox b = tilted_box();
  const ClassedMesh m = box_mesh(b);
  ASSERT_EQ(m.vertices.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d sign((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    const Eigen::Vector3d expected = b.center + b.axes * sign.cwiseProduct(b.half_extents);
    EXPECT_TRUE(m.vertices[i].cast<double>().isApprox(expected, 1e-6)) << i;
  }
}

TEST(OrientedBox, FacesAreWoundOutwardsAndCoverTheSurface) {
  const OrientedBox b = tilted_box();
  const ClassedMesh m = box_mesh(b);
  ASSERT_EQ(m.triangle_count(), 12u);
  double area = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const Eigen::Vector3d p0 = m.vertices[m.indices[t]].cast<double>();
    const Eigen::Vector3d p1 = m.vertices[m.indices[t + 1]].cast<double>();
    const Eigen::Vector3d p2 = m.vertices[m.indices[t + 2]].cast<double>();
    const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
    area += 0.5 * n.norm();
    const Eigen::Vector3d centroid = (p0 + p1 + p2) / 3;
    EXPECT_GT(n.dot(centroid - b.center), 0) << "triangle " << t / 3 << " faces inwards";
  }
  const Eigen::Vector3d s = 2 * b.half_extents;
  EXPECT_NEAR(area, 2 * (s.x() * s.y() + s.y() * s.z() + s.x() * s.z()), 1e-5);
}

TEST(OrientedBox, NoBottomLeavesOutTheLocalMinusZFace) {
  const ClassedMesh m = box_mesh(yawed_box({0, 0, 0.6}, {2, 0.1, 1.2}, 0.4), BoxFaces::NoBottom);
  ASSERT_EQ(m.triangle_count(), 10u);
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const bool all_low = m.vertices[m.indices[t]].z() < 1e-6f && m.vertices[m.indices[t + 1]].z() < 1e-6f &&
                         m.vertices[m.indices[t + 2]].z() < 1e-6f;
    EXPECT_FALSE(all_low) << "triangle " << t / 3 << " lies on the bottom";
  }
}

TEST(OrientedBox, AppendedBoxesKeepTheirOwnCornersAndTriangles) {
  const OrientedBox a = tilted_box();
  const OrientedBox b = yawed_box({3, 1, 0.6}, {2, 0.1, 1.2}, 1.1);
  ClassedMesh both;
  append_box(both, a);
  append_box(both, b, BoxFaces::NoBottom);
  const ClassedMesh ma = box_mesh(a), mb = box_mesh(b, BoxFaces::NoBottom);
  ASSERT_EQ(both.vertices.size(), 16u);
  ASSERT_EQ(both.indices.size(), ma.indices.size() + mb.indices.size());
  for (std::size_t i = 0; i < ma.indices.size(); ++i) {
    EXPECT_EQ(both.vertices[both.indices[i]], ma.vertices[ma.indices[i]]);
  }
  for (std::size_t i = 0; i < mb.indices.size(); ++i) {
    EXPECT_EQ(both.vertices[both.indices[ma.indices.size() + i]], mb.vertices[mb.indices[i]]);
  }
}

TEST(OrientedBox, YawedBoxTurnsAboutZ) {
  const OrientedBox b = yawed_box({1, 2, 3}, {4, 2, 6}, std::numbers::pi / 2);
  EXPECT_TRUE(b.half_extents.isApprox(Eigen::Vector3d(2, 1, 3)));
  EXPECT_TRUE((b.axes * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_TRUE((b.axes * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
}

TEST(OrientedBox, BadBoxesAreRefused) {
  OrientedBox b = tilted_box();
  b.half_extents.y() = -0.1;
  EXPECT_THROW(box_mesh(b), Error);
  b = tilted_box();
  b.center.x() = std::nan("");
  EXPECT_THROW(box_mesh(b), Error);
}

}  // namespace
}  // namespace sarmap::geometry
