#include "engine/io/sarmap_sequence.hpp"

#include <span>
#include <string>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/sarmap_sequence_manifest.hpp"

namespace sarmap {
namespace {

void check_labels(std::span<const std::uint8_t> labels, const std::string& file, const char* property) {
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] >= kClassCount) {
      throw Error(ErrorCode::InvalidData, file + ": point " + std::to_string(i) + ": " + property + " " +
                                              std::to_string(labels[i]) + " is not a class id (0.." +
                                              std::to_string(kClassCount - 1) + ")");
    }
  }
}

class SarmapSequence final : public ScanSource {
 public:
  SarmapSequence(std::filesystem::path folder, SequenceManifest manifest, const InputLimits& limits)
      : folder_(std::move(folder)), manifest_(std::move(manifest)), limits_(limits) {}

  std::size_t size() const override { return manifest_.frames.size(); }

  bool next(Scan& scan) override {
    if (next_ >= manifest_.frames.size()) return false;
    const std::size_t index = next_++;  // past this frame even when reading it fails
    const SequenceManifestFrame& frame = manifest_.frames[index];
    const std::filesystem::path file = folder_ / frame.file;
    PointCloudFileInfo info;
    PointBuffer points = read_point_cloud(file, &info, limits_);
    if (points.has_labels()) check_labels(points.labels(), file.string(), "label");
    if (points.has_gt_labels()) check_labels(points.gt_labels(), file.string(), "gt_label");
    std::size_t dropped = info.dropped_non_finite;
    if (manifest_.points_frame == PointsFrame::Sensor) {
      frame.pose.apply(points);
      // A coordinate near the float limit can overflow once moved.
      dropped += points.remove_non_finite();
    }
    scan = Scan{};
    scan.points = std::move(points);
    scan.pose = frame.pose;
    scan.origin = frame.origin;
    scan.timestamp = frame.timestamp;
    scan.index = index;
    scan.source = file.string();
    scan.dropped_non_finite = dropped;
    return true;
  }

  void rewind() override { next_ = 0; }
  void skip_to(std::size_t frame) override { next_ = frame; }
  const SensorInfo& sensor() const override { return manifest_.sensor; }
  std::string layout() const override { return "sarmap"; }
  std::string arena_sha256() const override { return manifest_.arena_sha256; }

 private:
  std::filesystem::path folder_;
  SequenceManifest manifest_;
  InputLimits limits_;
  std::size_t next_ = 0;
};

}  // namespace

std::unique_ptr<ScanSource> open_sarmap_sequence(const std::filesystem::path& folder, const InputLimits& limits) {
  const std::filesystem::path json = folder / "sequence.json";
  SequenceManifest manifest = read_sequence_manifest(json);
  for (std::size_t i = 0; i < manifest.frames.size(); ++i) {
    const std::filesystem::path file = folder / manifest.frames[i].file;
    if (const std::string why = why_not_a_regular_file(file); !why.empty()) {
      throw Error(ErrorCode::Io, json.string() + ": frames[" + std::to_string(i) + "].file: " + file.string() + why);
    }
  }
  return std::make_unique<SarmapSequence>(folder, std::move(manifest), limits);
}

}  // namespace sarmap
