#include "engine/io_rosbag/pose_lookup.hpp"

#include <algorithm>
#include <numeric>
#include <set>
#include <sstream>

#include "engine/core/error.hpp"

namespace sarmap::ros1 {

namespace {

// a * b for rigid transforms, with no multiplication by an identity, so a
// one-edge chain gives exactly the pose of that edge.
Pose compose(const Pose& a, const Pose& b) {
  return Pose(a.rotation() * b.rotation(), a.rotation() * b.translation() + a.translation(), "tf chain");
}

Pose inverse(const Pose& a) {
  const Eigen::Matrix3d r = a.rotation().transpose();
  return Pose(r, -(r * a.translation()), "tf chain");
}

std::string seconds(double s) {
  std::ostringstream out;
  out.precision(15);
  out << s;
  return out.str();
}

}  // namespace

Pose pose_of(const RosTransform& t, const std::string& what) {
  return Pose::from_quaternion(t.qx, t.qy, t.qz, t.qw, t.translation, what);
}

void PoseTrack::add(double stamp, const Pose& pose) {
  stamps_.push_back(stamp);
  poses_.push_back(pose);
}

void PoseTrack::finish() {
  std::vector<std::size_t> order(stamps_.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return stamps_[a] < stamps_[b]; });
  std::vector<double> stamps;
  std::vector<Pose> poses;
  for (const std::size_t i : order) {
    stamps.push_back(stamps_[i]);
    poses.push_back(poses_[i]);
  }
  stamps_ = std::move(stamps);
  poses_ = std::move(poses);
}

std::optional<Pose> PoseTrack::nearest(double stamp, double tolerance) const {
  const auto after = std::lower_bound(stamps_.begin(), stamps_.end(), stamp);
  std::optional<std::size_t> best;
  double distance = 0;
  if (after != stamps_.begin()) {
    best = static_cast<std::size_t>(after - stamps_.begin()) - 1;
    distance = stamp - stamps_[*best];
  }
  if (after != stamps_.end() && (!best || *after - stamp < distance)) {
    best = static_cast<std::size_t>(after - stamps_.begin());
    distance = *after - stamp;
  }
  if (!best || !(distance <= tolerance)) return std::nullopt;
  return poses_[*best];
}

void TfTree::add(const StampedTransform& t, bool is_static, const std::string& what) {
  Edge& edge = edges_[t.child_frame_id];
  edge.parent = t.header.frame_id;
  edge.is_static = edge.is_static || is_static;
  edge.track.add(is_static ? 0.0 : t.header.stamp, pose_of(t.transform, what));
}

void TfTree::finish() {
  for (auto& [child, edge] : edges_) edge.track.finish();
}

bool TfTree::has_frame(const std::string& frame) const {
  if (edges_.count(frame)) return true;
  for (const auto& [child, edge] : edges_) {
    if (edge.parent == frame) return true;
  }
  return false;
}

std::vector<std::string> TfTree::frames() const {
  std::set<std::string> all;
  for (const auto& [child, edge] : edges_) {
    all.insert(child);
    all.insert(edge.parent);
  }
  return {all.begin(), all.end()};
}

Pose TfTree::edge_pose(const std::string& child, const Edge& edge, double stamp, double tolerance) {
  const std::optional<Pose> pose =
      edge.is_static ? edge.track.nearest(0.0, 0.0) : edge.track.nearest(stamp, tolerance);
  if (!pose) {
    throw Error(ErrorCode::InvalidData, "/tf: no transform from '" + edge.parent + "' to '" + child +
                                            "' within " + seconds(tolerance) + " s of " + seconds(stamp) +
                                            " s");
  }
  return *pose;
}

std::vector<std::pair<std::string, Pose>> TfTree::chain_to_root(const std::string& frame, double stamp,
                                                                double tolerance,
                                                                const std::string& fixed_frame) const {
  std::vector<std::pair<std::string, Pose>> chain;
  std::string at = frame;
  while (true) {
    const auto edge = edges_.find(at);
    if (edge == edges_.end() || at == fixed_frame) break;
    if (chain.size() > edges_.size()) {
      throw Error(ErrorCode::InvalidData, "/tf: the frames above '" + frame + "' form a loop");
    }
    const Pose pose = edge_pose(at, edge->second, stamp, tolerance);
    chain.emplace_back(at, pose);
    at = edge->second.parent;
  }
  return chain;
}

Pose TfTree::lookup(const std::string& fixed_frame, const std::string& frame, double stamp,
                    double tolerance) const {
  if (frame == fixed_frame) return Pose();
  // Both frames up towards the root; the fixed frame's chain stops where the
  // cloud's passed.
  const auto up = chain_to_root(frame, stamp, tolerance, fixed_frame);
  const std::string top = up.empty() ? frame : edges_.at(up.back().first).parent;
  std::optional<Pose> frame_in_top;  // pose of `frame` in `top`
  for (auto it = up.rbegin(); it != up.rend(); ++it) {
    frame_in_top = frame_in_top ? compose(*frame_in_top, it->second) : it->second;
  }
  if (top == fixed_frame) return frame_in_top ? *frame_in_top : Pose();
  // The fixed frame lies elsewhere in the tree: meet at a common ancestor.
  std::map<std::string, std::size_t> on_path;  // frame -> how many edges of `up` lead to it
  on_path[frame] = 0;
  for (std::size_t i = 0; i < up.size(); ++i) on_path[edges_.at(up[i].first).parent] = i + 1;
  std::optional<Pose> fixed_in_meet;  // pose of the fixed frame in the meeting frame
  std::string at = fixed_frame;
  for (std::size_t steps = 0; !on_path.count(at); ++steps) {
    const auto edge = edges_.find(at);
    if (edge == edges_.end() || steps > edges_.size()) {
      throw Error(ErrorCode::InvalidData, "/tf: frames '" + fixed_frame + "' and '" + frame +
                                              "' are not connected by /tf or /tf_static");
    }
    const Pose pose = edge_pose(at, edge->second, stamp, tolerance);
    fixed_in_meet = fixed_in_meet ? compose(pose, *fixed_in_meet) : pose;
    at = edge->second.parent;
  }
  // Pose of `frame` in the meeting frame: the first on_path[at] edges of `up`.
  std::optional<Pose> frame_in_meet;
  for (std::size_t i = on_path[at]; i-- > 0;) {
    frame_in_meet = frame_in_meet ? compose(*frame_in_meet, up[i].second) : up[i].second;
  }
  const Pose meet_to_fixed = fixed_in_meet ? inverse(*fixed_in_meet) : Pose();
  return frame_in_meet ? compose(meet_to_fixed, *frame_in_meet) : meet_to_fixed;
}

}  // namespace sarmap::ros1
