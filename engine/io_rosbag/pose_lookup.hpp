// Where the sensor was when a bag's cloud was taken: the nearest pose in time
// from one pose topic (PoseTrack), or the /tf chain between a fixed frame and
// the cloud's frame at that time (TfTree). Both refuse a pose farther in time
// than a tolerance; what to do then (skip the scan) is the caller's choice.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/pose.hpp"
#include "engine/io_rosbag/ros_messages.hpp"

namespace sarmap::ros1 {

// The rotation and translation a ROS transform stands for; throws
// sarmap::Error (InvalidData) naming `what` for a zero or non-finite quaternion.
Pose pose_of(const RosTransform& t, const std::string& what);

class PoseTrack {
 public:
  void add(double stamp, const Pose& pose);
  // Sorts by time; call once after the last add().
  void finish();
  std::size_t size() const { return stamps_.size(); }
  // The pose nearest in time to `stamp` (ties go to the earlier one), if it
  // is at most `tolerance` seconds away.
  std::optional<Pose> nearest(double stamp, double tolerance) const;

 private:
  std::vector<double> stamps_;
  std::vector<Pose> poses_;
};

class TfTree {
 public:
  // One edge: the pose of t.child_frame_id in t.header.frame_id. A static
  // edge (/tf_static) holds at every time.
  void add(const StampedTransform& t, bool is_static, const std::string& what);
  void finish();
  bool has_frame(const std::string& frame) const;
  std::vector<std::string> frames() const;
  // The pose of `frame` in `fixed_frame` at `stamp`: every edge on the path
  // between them taken nearest in time within `tolerance`. Throws
  // sarmap::Error (InvalidData) naming the frames and the edge that is
  // missing or too far in time.
  Pose lookup(const std::string& fixed_frame, const std::string& frame, double stamp, double tolerance) const;

 private:
  struct Edge {
    std::string parent;
    bool is_static = false;
    PoseTrack track;
  };
  // The pose of `child` in its parent at `stamp` (a static edge at any time);
  // throws sarmap::Error (InvalidData) naming both frames when none is
  // within `tolerance`.
  static Pose edge_pose(const std::string& child, const Edge& edge, double stamp, double tolerance);
  // Path from `frame` up to its root: each frame and the pose of it in its parent.
  std::vector<std::pair<std::string, Pose>> chain_to_root(const std::string& frame, double stamp,
                                                          double tolerance,
                                                          const std::string& fixed_frame) const;
  std::map<std::string, Edge> edges_;  // by child frame
};

}  // namespace sarmap::ros1
