#include "engine/io_rosbag/rosbag_sequence.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io_rosbag/pose_lookup.hpp"
#include "engine/io_rosbag/ros_messages.hpp"

namespace sarmap {
namespace {

constexpr const char* kCloudType = "sensor_msgs/PointCloud2";
constexpr const char* kOdometryType = "nav_msgs/Odometry";
constexpr const char* kPoseStampedType = "geometry_msgs/PoseStamped";
constexpr const char* kTfType = "tf2_msgs/TFMessage";

// librosbag reports problems as its own exceptions (ros::Exception and
// std::exception); sarmap's callers expect sarmap::Error naming the file.
template <class F>
auto guarded(const std::filesystem::path& path, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(ErrorCode::Parse, path.string() + ": not a readable ROS 1 bag: " + e.what());
  }
}

// The message's bytes, refused before allocating when the bag's index says
// it is larger than one input file may be (--max-file-mb).
std::vector<std::uint8_t> message_bytes(const rosbag::MessageInstance& m, const InputLimits& limits,
                                        const std::string& what) {
  if (m.size() > limits.max_file_bytes) {
    throw Error(ErrorCode::OutOfRange,
                what + ": " + std::to_string(m.size()) + " bytes, more than --max-file-mb allows");
  }
  std::vector<std::uint8_t> bytes(m.size());
  ros::serialization::OStream stream(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  m.write(stream);
  return bytes;
}

// topic -> datatype, for every connection of the bag.
std::map<std::string, std::string> topics_of(rosbag::Bag& bag) {
  rosbag::View all(bag);
  std::map<std::string, std::string> topics;
  for (const rosbag::ConnectionInfo* c : all.getConnections()) topics[c->topic] = c->datatype;
  return topics;
}

std::string topic_list(const std::map<std::string, std::string>& topics) {
  if (topics.empty()) return "the bag has no topics";
  std::string out = "the bag has:";
  for (const auto& [topic, type] : topics) out += " " + topic + " (" + type + ")";
  return out;
}

std::string pick_cloud_topic(const std::filesystem::path& path, const RosbagOptions& options,
                             const std::map<std::string, std::string>& topics) {
  const std::string bag = path.string();
  if (!options.cloud_topic.empty()) {
    const auto it = topics.find(options.cloud_topic);
    if (it == topics.end()) {
      throw Error(ErrorCode::InvalidArgument,
                  bag + ": no topic " + options.cloud_topic + " (--cloud-topic); " + topic_list(topics));
    }
    if (it->second != kCloudType) {
      throw Error(ErrorCode::InvalidArgument, bag + ": topic " + it->first + " holds " + it->second +
                                                  ", not " + kCloudType + " (--cloud-topic)");
    }
    return it->first;
  }
  std::vector<std::string> clouds;
  for (const auto& [topic, type] : topics) {
    if (type == kCloudType) clouds.push_back(topic);
  }
  if (clouds.size() == 1) return clouds.front();
  throw Error(ErrorCode::InvalidArgument,
              bag +
                  (clouds.empty() ? ": no " + std::string(kCloudType) + " topic; "
                                  : ": more than one " + std::string(kCloudType) +
                                        " topic: choose one with --cloud-topic; ") +
                  topic_list(topics));
}

class RosbagSequence final : public ScanSource {
 public:
  RosbagSequence(const std::filesystem::path& path, const RosbagOptions& options,
                 const ScanSequenceOptions& sequence_options)
      : path_(path),
        options_(options),
        tolerance_(sequence_options.max_time_difference),
        limits_(sequence_options.limits) {
    if (!(tolerance_ >= 0))
      throw Error(ErrorCode::InvalidArgument, "max_time_difference must not be negative");
    if (!options.pose_topic.empty() && !options.fixed_frame.empty()) {
      throw Error(ErrorCode::InvalidArgument,
                  "--pose-topic and --fixed-frame are two pose sources: give one");
    }
    guarded(path_, [&] {
      bag_.open(path_.string(), rosbag::bagmode::Read);
      const auto topics = topics_of(bag_);
      cloud_topic_ = pick_cloud_topic(path_, options_, topics);
      read_poses(topics);
      rosbag::View clouds(bag_, rosbag::TopicQuery(cloud_topic_));
      size_ = clouds.size();
      return 0;
    });
    rewind();
  }

  std::size_t size() const override { return size_; }

  bool next(Scan& scan) override {
    return guarded(path_, [&] {
      if (next_ >= size_ || it_ == view_->end()) return false;
      const std::size_t index = next_++;
      const rosbag::MessageInstance message = *it_;
      ++it_;  // past this message even when it cannot be used
      const std::string what = path_.string() + " " + cloud_topic_ + " message " + std::to_string(index);
      ros1::CloudMessage cloud =
          ros1::decode_point_cloud2(message_bytes(message, limits_, what), what, limits_);
      // A cloud without a stamp is placed at the time the bag recorded it.
      const double stamp = cloud.header.stamp > 0 ? cloud.header.stamp : message.getTime().toSec();
      const Pose pose = pose_at(stamp, cloud.header.frame_id, what);
      pose.apply(cloud.points);
      scan = Scan{};
      scan.dropped_non_finite = cloud.dropped_non_finite + cloud.points.remove_non_finite();
      scan.points = std::move(cloud.points);
      scan.pose = pose;
      scan.origin = pose.translation();
      scan.timestamp = stamp;
      scan.index = index;
      scan.source = what;
      return true;
    });
  }

  void rewind() override {
    guarded(path_, [&] {
      view_ = std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(cloud_topic_));
      it_ = view_->begin();
      next_ = 0;
      return 0;
    });
  }

  void skip_to(std::size_t frame) override {
    rewind();
    guarded(path_, [&] {
      while (next_ < frame && it_ != view_->end()) {
        ++it_;
        ++next_;
      }
      return 0;
    });
  }

  const SensorInfo& sensor() const override { return sensor_; }
  std::string layout() const override { return "rosbag"; }

 private:
  void read_poses(const std::map<std::string, std::string>& topics) {
    const std::string bag = path_.string();
    if (options_.fixed_frame.empty()) {
      pose_topic_ = options_.pose_topic;
      if (pose_topic_.empty()) {
        std::vector<std::string> candidates;
        for (const auto& [topic, type] : topics) {
          if (type == kOdometryType || type == kPoseStampedType) candidates.push_back(topic);
        }
        if (candidates.size() != 1) {
          throw Error(
              ErrorCode::InvalidArgument,
              bag + ": " +
                  (candidates.empty() ? "no Odometry or PoseStamped topic" : "more than one pose topic") +
                  ": give --pose-topic, or --fixed-frame to place the clouds by /tf; " + topic_list(topics));
        }
        pose_topic_ = candidates.front();
      }
      const auto it = topics.find(pose_topic_);
      if (it == topics.end()) {
        throw Error(ErrorCode::InvalidArgument,
                    bag + ": no topic " + pose_topic_ + " (--pose-topic); " + topic_list(topics));
      }
      if (it->second != kOdometryType && it->second != kPoseStampedType) {
        throw Error(ErrorCode::InvalidArgument, bag + ": topic " + pose_topic_ + " holds " + it->second +
                                                    ", not " + kOdometryType + " or " + kPoseStampedType +
                                                    " (--pose-topic)");
      }
      const bool odometry = it->second == kOdometryType;
      rosbag::View view(bag_, rosbag::TopicQuery(pose_topic_));
      std::size_t n = 0;
      for (const rosbag::MessageInstance& m : view) {
        const std::string what = bag + " " + pose_topic_ + " message " + std::to_string(n++);
        const auto bytes = message_bytes(m, limits_, what);
        const ros1::StampedTransform t =
            odometry ? ros1::decode_odometry(bytes, what) : ros1::decode_pose_stamped(bytes, what);
        track_.add(t.header.stamp > 0 ? t.header.stamp : m.getTime().toSec(),
                   ros1::pose_of(t.transform, what));
      }
      track_.finish();
      if (track_.size() == 0)
        throw Error(ErrorCode::InvalidData, bag + ": topic " + pose_topic_ + " holds no messages");
      return;
    }
    use_tf_ = true;
    std::vector<std::string> tf_topics;
    for (const char* topic : {"/tf", "/tf_static"}) {
      const auto it = topics.find(topic);
      if (it != topics.end() && it->second == kTfType) tf_topics.push_back(topic);
    }
    if (tf_topics.empty()) {
      throw Error(ErrorCode::InvalidArgument,
                  bag + ": --fixed-frame needs /tf or /tf_static (" + kTfType + "); " + topic_list(topics));
    }
    rosbag::View view(bag_, rosbag::TopicQuery(tf_topics));
    std::size_t n = 0;
    for (const rosbag::MessageInstance& m : view) {
      const std::string what = bag + " " + m.getTopic() + " message " + std::to_string(n++);
      for (const ros1::StampedTransform& t : ros1::decode_tf_message(message_bytes(m, limits_, what), what)) {
        tf_.add(t, m.getTopic() == "/tf_static", what);
      }
    }
    tf_.finish();
    if (!tf_.has_frame(options_.fixed_frame)) {
      std::string frames;
      for (const std::string& f : tf_.frames()) frames += " " + f;
      throw Error(ErrorCode::InvalidArgument,
                  bag + ": /tf has no frame '" + options_.fixed_frame +
                      "' (--fixed-frame); its frames:" + (frames.empty() ? " none" : frames));
    }
  }

  Pose pose_at(double stamp, const std::string& frame, const std::string& what) const {
    if (use_tf_) {
      try {
        return tf_.lookup(options_.fixed_frame, frame, stamp, tolerance_);
      } catch (const Error& e) {
        throw Error(e.code(), what + ": " + e.what());
      }
    }
    const std::optional<Pose> pose = track_.nearest(stamp, tolerance_);
    if (!pose) {
      std::ostringstream msg;
      msg.precision(15);
      msg << what << ": no pose on " << pose_topic_ << " within " << tolerance_ << " s of the cloud's stamp "
          << stamp << " s (--max-time-difference)";
      throw Error(ErrorCode::InvalidData, msg.str());
    }
    return *pose;
  }

  std::filesystem::path path_;
  RosbagOptions options_;
  double tolerance_;
  InputLimits limits_;
  rosbag::Bag bag_;
  std::string cloud_topic_;
  std::string pose_topic_;
  bool use_tf_ = false;
  ros1::PoseTrack track_;
  ros1::TfTree tf_;
  std::size_t size_ = 0;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  std::size_t next_ = 0;
  SensorInfo sensor_;
};

}  // namespace

bool is_rosbag_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".bag";
}

std::unique_ptr<ScanSource> open_rosbag_sequence(const std::filesystem::path& path,
                                                 const RosbagOptions& options,
                                                 const ScanSequenceOptions& sequence_options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw Error(ErrorCode::Io, path.string() + ": no such bag file");
  return std::make_unique<RosbagSequence>(path, options, sequence_options);
}

}  // namespace sarmap
