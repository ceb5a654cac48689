// Simulates an arena's sensor along its trajectory: casts the sensor's rays
// into the arena's Embree scene (TBB-parallel over rows), adds the noise
// model's error to each depth / range and returns world-frame points labelled
// with the class of the surface they hit. Deterministic for a seed, whatever
// the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "engine/core/pose.hpp"
#include "engine/core/scan.hpp"
#include "engine/geometry/triangle_scene.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/sensor_rays.hpp"

namespace sarmap::sim {

using geometry::RayBatchMode;

struct SimulationOptions {
  std::uint64_t seed = 0;
  // False casts noise-free, dropout-free rays whatever the arena says.
  bool noise = true;
  RayBatchMode batch_mode = RayBatchMode::Packet16;
};

class Simulator {
 public:
  explicit Simulator(const Arena& arena, SimulationOptions options = {});

  std::size_t frame_count() const { return poses_.size(); }
  const std::vector<Pose>& poses() const { return poses_; }
  const SensorRays& rays() const { return rays_; }
  const geometry::TriangleScene& scene() const { return *scene_; }
  const Arena& arena() const { return arena_; }

  // One frame: world-frame points with ground-truth labels, its pose and origin.
  Scan simulate(std::size_t frame) const;

  // The noise-free ray parameter of every ray of a frame (depth for a depth
  // camera, range for a LiDAR; infinity when nothing is hit within the
  // sensor's range) and its class. Spans hold rays().directions.size() entries.
  void cast_frame(std::size_t frame, std::span<float> t, std::span<std::uint8_t> labels) const;

  // Whether a ray parameter is a return the sensor reports (within [min, max] range).
  bool in_range(float t) const { return t >= arena_.sensor.min_range && t <= arena_.sensor.max_range; }

 private:
  Arena arena_;
  SimulationOptions options_;
  std::unique_ptr<geometry::TriangleScene> scene_;
  SensorRays rays_;
  std::vector<Pose> poses_;
};

// Writes frames [0, max_frames) (all when 0) as a sarmap sequence folder,
// first removing the sequence a SequenceWriter wrote there before
// (remove_written_sequence; other files stay). sequence.json records the
// arena's sha256 when it has one. `progress(frame, points)` is called after
// each frame when given.
void write_simulated_sequence(const Simulator& simulator, const std::filesystem::path& folder,
                              std::size_t max_frames = 0,
                              const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace sarmap::sim
