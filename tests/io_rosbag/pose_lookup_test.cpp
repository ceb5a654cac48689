// Nearest-in-time poses and /tf chains: a chain of edges composed in order,
// a fixed frame in another branch of the tree, static edges, and the errors
// for an edge too far in time or frames that are not connected.
#include "engine/io_rosbag/pose_lookup.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/core/error.hpp"

namespace sarmap::ros1 {
namespace {

using ::testing::HasSubstr;

StampedTransform edge(const std::string& parent, const std::string& child, double stamp, Eigen::Vector3d t,
                      double yaw = 0) {
  StampedTransform e;
  e.header.frame_id = parent;
  e.header.stamp = stamp;
  e.child_frame_id = child;
  e.transform.translation = t;
  e.transform.qz = std::sin(yaw / 2);
  e.transform.qw = std::cos(yaw / 2);
  return e;
}

TEST(PoseTrack, NearestWithinToleranceTiesToTheEarlier) {
  PoseTrack track;
  track.add(2.0, Pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(2, 0, 0)));
  track.add(1.0, Pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 0, 0)));
  track.finish();
  EXPECT_EQ(track.nearest(1.4, 0.5)->translation().x(), 1.0);
  EXPECT_EQ(track.nearest(1.5, 0.5)->translation().x(), 1.0);
  EXPECT_EQ(track.nearest(1.6, 0.5)->translation().x(), 2.0);
  EXPECT_FALSE(track.nearest(2.6, 0.5));
  EXPECT_FALSE(PoseTrack().nearest(0, 1));
}

TEST(TfTree, ComposesAChainAndMeetsAFixedFrameInAnotherBranch) {
  TfTree tf;
  const double quarter = M_PI / 2;
  tf.add(edge("map", "odom", 0, {10, 0, 0}, quarter), true, "static");
  tf.add(edge("odom", "base", 1.0, {1, 0, 0}), false, "tf");
  tf.add(edge("odom", "base", 2.0, {2, 0, 0}), false, "tf");
  tf.add(edge("base", "lidar", 0, {0, 0, 1}), true, "static");
  tf.add(edge("map", "dock", 5.0, {0, 5, 0}), false, "tf");
  tf.finish();
  // lidar in map at t = 1: map -> odom (rotated a quarter turn) -> base (1 m along odom's x) -> lidar.
  const Pose p = tf.lookup("map", "lidar", 1.01, 0.05);
  EXPECT_NEAR((p.translation() - Eigen::Vector3d(10, 1, 1)).norm(), 0, 1e-12);
  EXPECT_NEAR((p * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(10, 2, 1)).norm(), 0, 1e-12);
  // The same seen from odom and from dock, a sibling branch of map.
  EXPECT_NEAR((tf.lookup("odom", "lidar", 2.0, 0.05).translation() - Eigen::Vector3d(2, 0, 1)).norm(), 0,
              1e-12);
  const Pose from_dock = tf.lookup("dock", "lidar", 1.0, 10.0);
  EXPECT_NEAR((from_dock.translation() - Eigen::Vector3d(10, -4, 1)).norm(), 0, 1e-12);
  EXPECT_NEAR((tf.lookup("lidar", "lidar", 0, 0).translation()).norm(), 0, 0);

  EXPECT_THAT(
      [&] {
        try {
          tf.lookup("map", "lidar", 3.5, 0.05);
        } catch (const Error& e) {
          return std::string(e.what());
        }
        return std::string();
      }(),
      HasSubstr("no transform from 'odom' to 'base' within 0.05 s of 3.5 s"));
  TfTree apart;
  apart.add(edge("a", "b", 0, {0, 0, 0}), true, "s");
  apart.add(edge("c", "d", 0, {0, 0, 0}), true, "s");
  apart.finish();
  EXPECT_THROW(apart.lookup("a", "d", 0, 1), Error);
  EXPECT_TRUE(apart.has_frame("c"));
  EXPECT_FALSE(apart.has_frame("e"));
}

}  // namespace
}  // namespace sarmap::ros1
