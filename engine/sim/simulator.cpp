#include "engine/sim/simulator.hpp"

#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/core/error.hpp"
#include "engine/io/sequence_writer.hpp"
#include "engine/sim/arena_mesh.hpp"
#include "engine/sim/ray_noise.hpp"
#include "engine/sim/trajectory.hpp"

namespace sarmap::sim {
namespace {

// Rotates a row of sensor-frame directions into the world frame.
void rotate_row(const Eigen::Matrix3f& r, std::span<const Eigen::Vector3f> in, std::span<Eigen::Vector3f> out) {
  for (std::size_t i = 0; i < in.size(); ++i) out[i] = r * in[i];
}

}  // namespace

Simulator::Simulator(const Arena& arena, SimulationOptions options)
    : arena_(arena),
      options_(options),
      scene_(std::make_unique<geometry::TriangleScene>(arena_meshes(arena))),
      rays_(make_sensor_rays(arena.sensor)),
      poses_(trajectory_poses(arena, *scene_)) {}

void Simulator::cast_frame(std::size_t frame, std::span<float> t, std::span<std::uint8_t> labels) const {
  const std::size_t n = rays_.directions.size();
  if (frame >= poses_.size() || t.size() != n || labels.size() != n) {
    throw Error(ErrorCode::InvalidArgument, "Simulator::cast_frame: frame or output size out of range");
  }
  const Pose& pose = poses_[frame];
  const Eigen::Matrix3f r = pose.rotation().cast<float>();
  const Eigen::Vector3f origin = pose.translation().cast<float>();
  const auto cols = static_cast<std::size_t>(rays_.cols);
  const auto t_far = static_cast<float>(arena_.sensor.max_range);
  std::vector<Eigen::Vector3f> world(n);
  tbb::parallel_for(tbb::blocked_range<int>(0, rays_.rows), [&](const tbb::blocked_range<int>& range) {
    for (int row = range.begin(); row != range.end(); ++row) {
      const std::size_t first = static_cast<std::size_t>(row) * cols;
      std::span<Eigen::Vector3f> dirs(world.data() + first, cols);
      rotate_row(r, std::span<const Eigen::Vector3f>(rays_.directions.data() + first, cols), dirs);
      scene_->intersect_batch(origin, dirs, 0.0f, t_far, t.subspan(first, cols), labels.subspan(first, cols),
                              options_.batch_mode);
      for (std::size_t i = first; i < first + cols; ++i) {
        if (!in_range(t[i])) t[i] = std::numeric_limits<float>::infinity();
      }
    }
  });
}

Scan Simulator::simulate(std::size_t frame) const {
  const std::size_t n = rays_.directions.size();
  std::vector<float> t(n);
  std::vector<std::uint8_t> labels(n);
  cast_frame(frame, t, labels);
  const Pose& pose = poses_[frame];
  const Eigen::Matrix3d& r = pose.rotation();
  const Eigen::Vector3d& o = pose.translation();
  // Noise per ray in parallel, then a serial compaction in ray order: the
  // output order never depends on scheduling.
  std::vector<Eigen::Vector3f> points(n);
  std::vector<std::uint8_t> keep(n, 0);
  const NoiseSpec noise = options_.noise ? arena_.sensor.noise : NoiseSpec{};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (!std::isfinite(t[i])) continue;
      double measured = 0;
      if (!apply_noise(noise, t[i], ray_key(options_.seed, frame, i), measured) || !(measured > 0)) continue;
      const Eigen::Vector3d p = o + r * (rays_.directions[i].cast<double>() * measured);
      points[i] = p.cast<float>();
      keep[i] = 1;
    }
  });
  Scan scan;
  scan.pose = pose;
  scan.origin = o;
  scan.index = frame;
  scan.timestamp = static_cast<double>(frame);
  scan.source = arena_.name + " frame " + std::to_string(frame);
  scan.points.enable_labels();
  std::size_t count = 0;
  for (std::uint8_t k : keep) count += k;
  scan.points.resize(count);
  auto xs = scan.points.x();
  auto ys = scan.points.y();
  auto zs = scan.points.z();
  auto ls = scan.points.labels();
  std::size_t out = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    xs[out] = points[i].x();
    ys[out] = points[i].y();
    zs[out] = points[i].z();
    ls[out] = labels[i];
    ++out;
  }
  return scan;
}

void write_simulated_sequence(const Simulator& simulator, const std::filesystem::path& folder,
                              std::size_t max_frames,
                              const std::function<void(std::size_t, std::size_t)>& progress) {
  const std::size_t frames =
      max_frames == 0 ? simulator.frame_count() : std::min(max_frames, simulator.frame_count());
  // What an earlier, longer simulation into this folder left must not stay
  // beside the new frames; files it did not write stay.
  remove_written_sequence(folder);
  SequenceWriter writer(folder, sensor_info(simulator.arena().sensor));
  // Runs of the sequence carry it into their manifest; eval checks it.
  if (!simulator.arena().sha256.empty()) writer.set_arena_sha256(simulator.arena().sha256);
  for (std::size_t f = 0; f < frames; ++f) {
    const Scan scan = simulator.simulate(f);
    writer.add(scan);
    if (progress) progress(f, scan.points.size());
  }
  writer.finish();
}

}  // namespace sarmap::sim
