#include "engine/io/single_cloud_source.hpp"

#include "engine/core/error.hpp"
#include "engine/io/point_cloud_file.hpp"

namespace sarmap {
namespace {

class SingleCloudSource final : public ScanSource {
 public:
  SingleCloudSource(std::filesystem::path path, const InputLimits& limits) : path_(std::move(path)), limits_(limits) {}

  std::size_t size() const override { return 1; }
  bool next(Scan& scan) override {
    if (done_) return false;
    done_ = true;  // even when reading fails
    PointCloudFileInfo info;
    PointBuffer points = read_point_cloud(path_, &info, limits_);
    scan = Scan{};
    scan.points = std::move(points);
    scan.source = path_.string();
    scan.dropped_non_finite = info.dropped_non_finite;
    return true;
  }
  void rewind() override { done_ = false; }
  void skip_to(std::size_t frame) override { done_ = frame > 0; }
  const SensorInfo& sensor() const override { return sensor_; }
  std::string layout() const override { return "cloud"; }

 private:
  std::filesystem::path path_;
  InputLimits limits_;
  SensorInfo sensor_;
  bool done_ = false;
};

}  // namespace

std::unique_ptr<ScanSource> open_single_cloud(const std::filesystem::path& path, const InputLimits& limits) {
  point_cloud_format_of(path);  // throws for an extension other than .ply / .pcd
  if (!std::filesystem::is_regular_file(path)) {
    throw Error(ErrorCode::Io, path.string() + ": no such point-cloud file");
  }
  return std::make_unique<SingleCloudSource>(path, limits);
}

}  // namespace sarmap
