#include "engine/io/tum_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/depth_image_back_projection.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/intrinsics.hpp"
#include "engine/io/sequence_text.hpp"

namespace sarmap {
namespace {

struct TumFrame {
  std::filesystem::path depth_file;
  double timestamp;
  Pose pose;
};

struct GroundTruth {
  std::vector<double> times;
  std::vector<Pose> poses;
};

GroundTruth read_ground_truth(const std::filesystem::path& path) {
  const std::string file = path.string();
  GroundTruth gt;
  for (const TextRow& row : read_text_rows(path)) {
    expect_token_count(row, 8, file, "timestamp tx ty tz qx qy qz qw");
    static constexpr const char* kFields[8] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
    double v[8];
    for (int i = 0; i < 8; ++i) v[i] = parse_number(row.tokens[i], file, row.line, kFields[i]);
    if (!gt.times.empty() && v[0] < gt.times.back()) {
      throw Error(ErrorCode::InvalidData,
                  at_line(file, row.line, "timestamp " + row.tokens[0] + " is earlier than the line before"));
    }
    gt.times.push_back(v[0]);
    gt.poses.push_back(Pose::from_quaternion(v[4], v[5], v[6], v[7], Eigen::Vector3d(v[1], v[2], v[3]),
                                             file + ":" + std::to_string(row.line)));
  }
  if (gt.times.empty()) throw Error(ErrorCode::InvalidData, file + ": no ground-truth poses");
  return gt;
}

class TumSequence final : public ScanSource {
 public:
  TumSequence(std::vector<TumFrame> frames, std::size_t skipped, SensorInfo sensor, DepthDecoding decoding)
      : frames_(std::move(frames)), skipped_(skipped), sensor_(std::move(sensor)), decoding_(decoding) {}

  std::size_t size() const override { return frames_.size(); }

  bool next(Scan& scan) override {
    if (next_ >= frames_.size()) return false;
    const std::size_t index = next_++;  // past this frame even when reading it fails
    const TumFrame& frame = frames_[index];
    scan = read_depth_png_scan(frame.depth_file, *sensor_.intrinsics, decoding_, frame.pose, frame.timestamp,
                               index);
    return true;
  }

  void rewind() override { next_ = 0; }
  void skip_to(std::size_t frame) override { next_ = frame; }
  const SensorInfo& sensor() const override { return sensor_; }
  std::string layout() const override { return "tum"; }
  std::size_t skipped_frames() const override { return skipped_; }

 private:
  std::vector<TumFrame> frames_;
  std::size_t skipped_;
  SensorInfo sensor_;
  DepthDecoding decoding_;
  std::size_t next_ = 0;
};

}  // namespace

std::vector<std::optional<std::size_t>> associate_nearest(std::span<const double> queries,
                                                          std::span<const double> refs, double tolerance) {
  std::vector<std::optional<std::size_t>> out(queries.size());
  for (std::size_t q = 0; q < queries.size(); ++q) {
    const double t = queries[q];
    const auto after = std::lower_bound(refs.begin(), refs.end(), t);
    std::optional<std::size_t> best;
    double best_distance = 0;
    if (after != refs.begin()) {
      best = static_cast<std::size_t>(after - refs.begin()) - 1;
      best_distance = t - refs[*best];
    }
    if (after != refs.end() && (!best || *after - t < best_distance)) {
      best = static_cast<std::size_t>(after - refs.begin());
      best_distance = *after - t;
    }
    if (best && best_distance <= tolerance) out[q] = best;
  }
  return out;
}

std::unique_ptr<ScanSource> open_tum_sequence(const std::filesystem::path& folder,
                                              const ScanSequenceOptions& options) {
  const std::filesystem::path depth_list = folder / "depth.txt";
  const std::filesystem::path gt_file = folder / "groundtruth.txt";
  if (!std::filesystem::exists(gt_file)) {
    throw Error(ErrorCode::Io, folder.string() +
                                   ": TUM RGB-D folder has depth.txt but no groundtruth.txt "
                                   "(the poses); cannot place the frames");
  }
  if (!(options.max_time_difference >= 0)) {
    throw Error(ErrorCode::InvalidArgument, "max_time_difference must not be negative");
  }

  SensorInfo sensor;
  sensor.type = SensorType::DepthCamera;
  sensor.max_range = options.max_depth;
  sensor.intrinsics =
      find_intrinsics(options.intrinsics_file, folder / "intrinsics.json", "TUM RGB-D folder");

  const std::string list_name = depth_list.string();
  std::vector<double> times;
  std::vector<std::filesystem::path> files;
  for (const TextRow& row : read_text_rows(depth_list)) {
    expect_token_count(row, 2, list_name, "timestamp filename");
    const double t = parse_number(row.tokens[0], list_name, row.line, "timestamp");
    if (!times.empty() && t < times.back()) {
      throw Error(
          ErrorCode::InvalidData,
          at_line(list_name, row.line, "timestamp " + row.tokens[0] + " is earlier than the line before"));
    }
    const std::filesystem::path file = folder / row.tokens[1];
    if (const std::string why = why_not_a_regular_file(file); !why.empty()) {
      throw Error(ErrorCode::Io, at_line(list_name, row.line, "depth image " + file.string() + why));
    }
    times.push_back(t);
    files.push_back(file);
  }
  if (times.empty()) throw Error(ErrorCode::InvalidData, list_name + ": lists no depth images");

  const GroundTruth gt = read_ground_truth(gt_file);
  const auto matches = associate_nearest(times, gt.times, options.max_time_difference);
  std::vector<TumFrame> frames;
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (matches[i]) frames.push_back({files[i], times[i], gt.poses[*matches[i]]});
  }
  if (frames.empty()) {
    std::ostringstream msg;
    msg << folder.string() << ": none of the " << times.size()
        << " depth frames has a ground-truth pose within " << options.max_time_difference << " s";
    throw Error(ErrorCode::InvalidData, msg.str());
  }
  const std::size_t skipped = times.size() - frames.size();
  DepthDecoding decoding;
  decoding.units_per_metre = kTumDepthUnitsPerMetre;
  decoding.max_depth = options.max_depth;
  decoding.limits = options.limits;
  return std::make_unique<TumSequence>(std::move(frames), skipped, std::move(sensor), decoding);
}

}  // namespace sarmap
