#include "engine/io/seven_scenes_sequence.hpp"

#include <algorithm>
#include <charconv>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/depth_image_back_projection.hpp"
#include "engine/io/intrinsics.hpp"
#include "engine/io/sequence_text.hpp"

namespace sarmap {
namespace {

struct SevenScenesFrame {
  unsigned long number;
  std::filesystem::path depth_file;
  std::filesystem::path pose_file;
};

Pose read_pose_matrix(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::vector<TextRow> rows = read_text_rows(path);
  if (rows.size() != 4) {
    throw Error(ErrorCode::Parse, file + ": expected a 4x4 pose matrix (4 lines of 4 numbers), got " +
                                      std::to_string(rows.size()) + " lines");
  }
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    expect_token_count(rows[r], 4, file, "one row of the 4x4 camera-to-world matrix");
    for (int c = 0; c < 4; ++c) {
      m(r, c) = parse_number(rows[r].tokens[c], file, rows[r].line,
                             "M[" + std::to_string(r) + "][" + std::to_string(c) + "]");
    }
  }
  return Pose::from_matrix(m, file);
}

class SevenScenesSequence final : public ScanSource {
 public:
  SevenScenesSequence(std::vector<SevenScenesFrame> frames, SensorInfo sensor, DepthDecoding decoding)
      : frames_(std::move(frames)), sensor_(std::move(sensor)), decoding_(decoding) {}

  std::size_t size() const override { return frames_.size(); }

  bool next(Scan& scan) override {
    if (next_ >= frames_.size()) return false;
    const std::size_t index = next_++;  // past this frame even when reading it fails
    const SevenScenesFrame& frame = frames_[index];
    const Pose pose = read_pose_matrix(frame.pose_file);
    scan = read_depth_png_scan(frame.depth_file, *sensor_.intrinsics, decoding_, pose,
                               static_cast<double>(frame.number) / kSevenScenesFrameRate, index);
    return true;
  }

  void rewind() override { next_ = 0; }
  void skip_to(std::size_t frame) override { next_ = frame; }
  const SensorInfo& sensor() const override { return sensor_; }
  std::string layout() const override { return "7scenes"; }

 private:
  std::vector<SevenScenesFrame> frames_;
  SensorInfo sensor_;
  DepthDecoding decoding_;
  std::size_t next_ = 0;
};

}  // namespace

std::optional<unsigned long> seven_scenes_frame_number(std::string_view name) {
  constexpr std::string_view kPrefix = "frame-";
  constexpr std::string_view kSuffix = ".depth.png";
  if (name.size() <= kPrefix.size() + kSuffix.size() || !name.starts_with(kPrefix) ||
      !name.ends_with(kSuffix)) {
    return std::nullopt;
  }
  const std::string_view digits = name.substr(kPrefix.size(), name.size() - kPrefix.size() - kSuffix.size());
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  unsigned long number = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), number);
  if (ec != std::errc() || end != digits.data() + digits.size()) return std::nullopt;
  return number;
}

std::unique_ptr<ScanSource> open_seven_scenes_sequence(const std::filesystem::path& folder,
                                                       const ScanSequenceOptions& options) {
  SensorInfo sensor;
  sensor.type = SensorType::DepthCamera;
  sensor.max_range = options.max_depth;
  sensor.intrinsics =
      find_intrinsics(options.intrinsics_file, folder / "camera-intrinsics.txt", "7-Scenes folder");

  std::vector<SevenScenesFrame> frames;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    const auto number = seven_scenes_frame_number(name);
    if (!number) continue;
    std::string stem = name.substr(0, name.size() - std::string_view(".depth.png").size());
    std::filesystem::path pose_file = folder / (stem + ".pose.txt");
    if (!std::filesystem::is_regular_file(pose_file)) {
      throw Error(ErrorCode::Io, entry.path().string() + ": missing pose file " + pose_file.string());
    }
    frames.push_back({*number, entry.path(), std::move(pose_file)});
  }
  if (frames.empty()) {
    throw Error(ErrorCode::InvalidData, folder.string() + ": no frame-NNNNNN.depth.png files");
  }
  std::sort(frames.begin(), frames.end(),
            [](const SevenScenesFrame& a, const SevenScenesFrame& b) { return a.number < b.number; });
  for (std::size_t i = 1; i < frames.size(); ++i) {
    if (frames[i].number == frames[i - 1].number) {
      throw Error(ErrorCode::InvalidData, folder.string() + ": frame number " +
                                              std::to_string(frames[i].number) + " appears twice (" +
                                              frames[i - 1].depth_file.filename().string() + ", " +
                                              frames[i].depth_file.filename().string() + ")");
    }
  }
  DepthDecoding decoding;
  decoding.units_per_metre = kSevenScenesDepthUnitsPerMetre;
  decoding.max_value_is_invalid = true;
  decoding.max_depth = options.max_depth;
  decoding.limits = options.limits;
  return std::make_unique<SevenScenesSequence>(std::move(frames), std::move(sensor), decoding);
}

}  // namespace sarmap
