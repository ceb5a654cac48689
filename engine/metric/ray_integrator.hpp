// Writes one scan into the metric map: a DDA ray from the sensor origin to
// every end point, misses along it and a hit at its end, with OctoMap's
// discretised per-scan semantics, parallel over oneTBB and bit-identical for
// any thread count.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "engine/core/point_buffer.hpp"
#include "engine/core/scan.hpp"
#include "engine/metric/integration_settings.hpp"
#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

class RayIntegrator {
 public:
  // Throws sarmap::Error (InvalidArgument) for a negative or non-finite max_range.
  explicit RayIntegrator(const IntegratorSettings& settings = {});
  ~RayIntegrator();
  RayIntegrator(RayIntegrator&&) noexcept;
  RayIntegrator& operator=(RayIntegrator&&) noexcept;

  const IntegratorSettings& settings() const { return settings_; }

  // Bytes of scratch kept between scans (the three scans' rays in flight,
  // every thread's masks, the update's tables), apart from the map's own
  // (MetricMap::memory_bytes). Grows to the largest scan seen. It may run
  // beside trace() of a slot (whose bytes it counts as that slot's last
  // use left them), not beside apply(), integrate() or integrate_sequence().
  std::size_t scratch_bytes() const;

  // Integrates the scan's points (world frame) seen from origin. Each voxel is
  // updated at most once; a voxel hit in this scan is not also marked free.
  // Throws sarmap::Error before touching the map for an origin beyond the map
  // limits (OutOfRange) or a label that is not a class id (InvalidData).
  // Uses the calling thread's oneTBB arena; not reentrant per integrator.
  IntegrationStats integrate(MetricMap& map, const PointBuffer& points, const Eigen::Vector3d& origin);

  // integrate() in its two halves, for a caller that finds one scan's rays
  // while the scan before is written into the map (Mapper::integrate_stream):
  // trace() reads nothing of the map, so it may run beside apply() of
  // another slot, and apply() writes what trace() found in that slot. Each
  // slot holds one scan's rays from trace() until its apply(). integrate()
  // uses slot 0; resolution is the map's (read once by the caller: the map
  // may be being written). trace() throws as integrate() does; the stats it
  // returns are completed by apply(). Both throw sarmap::Error
  // (InvalidArgument) for a slot not below kSlots; apply() too for a slot
  // that holds no traced scan (never traced, its trace threw, or applied).
  static constexpr std::size_t kSlots = 3;
  IntegrationStats trace(std::size_t slot, double resolution, const PointBuffer& points,
                         const Eigen::Vector3d& origin);
  void apply(MetricMap& map, std::size_t slot, IntegrationStats& stats);

  // Integrates the scans' points from their origins, in order: the same map
  // and per-scan figures as integrate() on each in turn, faster with several
  // threads because the next scan is traced while this one is applied (two
  // slots: the halves and the overlap of the Mapper's stream, so that the
  // benchmark measures the path users run). On an error in scan k (as
  // integrate() throws, the message naming the scan) the map holds scans
  // 0 .. k - 1 exactly.
  std::vector<IntegrationStats> integrate_sequence(MetricMap& map, std::span<const Scan> scans);

 private:
  struct Scratch;
  static void check_slot(std::size_t slot);
  IntegratorSettings settings_;
  std::unique_ptr<Scratch> scratch_;
};

}  // namespace sarmap::metric
