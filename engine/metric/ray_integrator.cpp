// One scan in four passes. ScanRays (scan_rays.hpp), without the map: (1) the
// distinct end voxels with their class observations (keys by a vector
// kernel, kernels/voxel_keys.hpp; grouped locally in parallel, merged in
// order: end_voxel_groups.hpp) and one ray per end voxel; (2) parallel DDA
// walks that only set "miss" bits in per-thread masks (no locks, no atomics),
// and the hits listed by block (grid_hit_list.hpp).
// ScanUpdate (scan_update.hpp), into the map: (3) a serial merge of the
// masks, each block's hits found, blocks created in sorted key order;
// (4) parallel updates, each block by one thread, hits overriding misses,
// begun on the blocks pass 3 has prepared while it prepares the rest.
//
// Passes 1-2 (trace) never read the map, so the next scan's can run while
// this scan's passes 3-4 (apply) write it: the serial parts of each half
// then run beside the parallel work of the other instead of leaving the
// second thread idle. A sequence of scans runs so (integrate_sequence), and
// so does the Mapper's stream (Mapper::integrate_stream), with the same two
// halves: the benchmark's sequence is the users' path. The map is the same
// as integrating the scans one by one, because the updates run one scan at
// a time, in order.
#include "engine/metric/ray_integrator.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <string>

#include <tbb/task_group.h>

#include "engine/core/error.hpp"
#include "engine/core/usable_threads.hpp"
#include "engine/metric/scan_rays.hpp"
#include "engine/metric/scan_update.hpp"

namespace sarmap::metric {

struct RayIntegrator::Scratch {
  // Three, so that scan k + 1's ends can be found while scan k is walked
  // and scan k - 1 is applied.
  std::array<ScanRays, RayIntegrator::kSlots> rays;
  // Whether a slot holds rays from trace() not yet applied: apply() takes
  // each scan once, never a failed trace's half or a scan already in.
  std::array<bool, RayIntegrator::kSlots> traced{};
  // Each slot's bytes as its last use left them, so that scratch_bytes()
  // can run beside a trace() of another slot without reading its buffers.
  std::array<std::atomic<std::size_t>, RayIntegrator::kSlots> rays_bytes{};

  void count(std::size_t slot) {
    rays_bytes[slot].store(rays[slot].memory_bytes(), std::memory_order_relaxed);
  }
  ScanUpdate update;
};

IntegrationStats& IntegrationStats::operator+=(const IntegrationStats& o) {
  points_in += o.points_in;
  points_rejected += o.points_rejected;
  end_voxels += o.end_voxels;
  rays += o.rays;
  voxel_visits += o.voxel_visits;
  hits += o.hits;
  misses += o.misses;
  blocks_created += o.blocks_created;
  dense_walks += o.dense_walks;
  dense_dedupes += o.dense_dedupes;
  return *this;
}

RayIntegrator::RayIntegrator(const IntegratorSettings& settings)
    : settings_(settings), scratch_(std::make_unique<Scratch>()) {
  for (std::size_t slot = 0; slot < kSlots; ++slot) scratch_->count(slot);
  if (!(settings.max_range >= 0.0) || !std::isfinite(settings.max_range)) {
    throw Error(ErrorCode::InvalidArgument,
                "ray integrator: max_range must be finite and >= 0, got " + std::to_string(settings.max_range));
  }
}
RayIntegrator::~RayIntegrator() = default;
RayIntegrator::RayIntegrator(RayIntegrator&&) noexcept = default;
RayIntegrator& RayIntegrator::operator=(RayIntegrator&&) noexcept = default;

std::size_t RayIntegrator::scratch_bytes() const {
  if (!scratch_) return 0;  // moved from
  std::size_t bytes = sizeof(Scratch) + scratch_->update.memory_bytes();
  for (const auto& slot : scratch_->rays_bytes) bytes += slot.load(std::memory_order_relaxed);
  return bytes;
}

IntegrationStats RayIntegrator::integrate(MetricMap& map, const PointBuffer& points,
                                          const Eigen::Vector3d& origin) {
  IntegrationStats stats = trace(0, map.resolution(), points, origin);
  apply(map, 0, stats);
  return stats;
}

void RayIntegrator::check_slot(std::size_t slot) {
  if (slot >= kSlots) {
    throw Error(ErrorCode::InvalidArgument, "ray integrator: slot " + std::to_string(slot) +
                                                " is not one of its " + std::to_string(kSlots));
  }
}

IntegrationStats RayIntegrator::trace(std::size_t slot, double resolution, const PointBuffer& points,
                                      const Eigen::Vector3d& origin) {
  Scratch& s = *scratch_;
  check_slot(slot);
  s.traced[slot] = false;
  IntegrationStats stats;
  try {
    s.rays[slot].compute(settings_, resolution, points, origin, stats);
  } catch (...) {
    s.count(slot);
    throw;
  }
  s.count(slot);
  s.traced[slot] = true;
  return stats;
}

void RayIntegrator::apply(MetricMap& map, std::size_t slot, IntegrationStats& stats) {
  Scratch& s = *scratch_;
  check_slot(slot);
  if (!s.traced[slot]) {
    throw Error(ErrorCode::InvalidArgument,
                "ray integrator: slot " + std::to_string(slot) + " holds no traced scan to apply");
  }
  s.traced[slot] = false;
  s.update.apply(map, s.rays[slot], stats);
  s.count(slot);
}

std::vector<IntegrationStats> RayIntegrator::integrate_sequence(MetricMap& map, std::span<const Scan> scans) {
  Scratch& s = *scratch_;
  s.traced.fill(false);  // every slot's rays are overwritten below
  // Their bytes counted again however the sequence ends (after the tasks below have).
  struct Recount {
    Scratch& scratch;
    ~Recount() {
      for (std::size_t slot = 0; slot < kSlots; ++slot) scratch.count(slot);
    }
  } const recount{s};
  std::vector<IntegrationStats> stats(scans.size());
  const std::size_t threads = usable_threads();
  const auto named = [](std::size_t k, const Error& e) {
    return Error(e.code(), "scan " + std::to_string(k) + ": " + e.what());
  };
  if (threads <= 1) {
    // Nothing to overlap with one thread, and a scan's update is faster
    // right after its rays, while they are in cache (overlapping them on one
    // thread measured slower: docs/perf-history.md).
    for (std::size_t k = 0; k < scans.size(); ++k) {
      try {
        stats[k] = integrate(map, scans[k].points, scans[k].origin);
      } catch (const Error& e) {
        throw named(k, e);
      }
    }
    return stats;
  }
  // The resolution is read once: the map is being written while scans' rays are traced.
  const double resolution = map.resolution();
  if (scans.empty()) return stats;
  try {
    stats[0] = trace(0, resolution, scans[0].points, scans[0].origin);
  } catch (const Error& e) {
    throw named(0, e);
  }
  // Scan k is applied in a task while this thread traces scan k + 1 into
  // the other slot (both halves' parallel loops share the arena's threads).
  for (std::size_t k = 0; k < scans.size(); ++k) {
    tbb::task_group writing;
    writing.run([&, k] { apply(map, k % 2, stats[k]); });
    if (k + 1 < scans.size()) {
      try {
        stats[k + 1] = trace((k + 1) % 2, resolution, scans[k + 1].points, scans[k + 1].origin);
      } catch (const Error& e) {
        writing.wait();  // scans 0 .. k are in the map; nothing of scan k + 1 is
        throw named(k + 1, e);
      } catch (...) {
        writing.wait();
        throw;
      }
    }
    writing.wait();
  }
  return stats;
}

}  // namespace sarmap::metric
