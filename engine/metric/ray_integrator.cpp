// One scan in four passes. ScanRays (scan_rays.hpp), without the map: (1) the
// distinct end voxels with their class observations (keys by a vector
// kernel, kernels/voxel_keys.hpp; grouped locally in parallel, merged in
// order: end_voxel_groups.hpp) and one ray per end voxel; (2) parallel DDA
// walks that only set "miss" bits in per-thread masks (no locks, no atomics).
// ScanUpdate (scan_update.hpp), into the map: (3) a serial merge of the
// masks, hits that override misses, blocks created in sorted key order;
// (4) parallel updates, one block per task.
#include "engine/metric/ray_integrator.hpp"

#include <cmath>
#include <string>

#include "engine/core/error.hpp"
#include "engine/metric/scan_rays.hpp"
#include "engine/metric/scan_update.hpp"

namespace sarmap::metric {

struct RayIntegrator::Scratch {
  ScanRays rays;
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
  if (!(settings.max_range >= 0.0) || !std::isfinite(settings.max_range)) {
    throw Error(ErrorCode::InvalidArgument,
                "ray integrator: max_range must be finite and >= 0, got " + std::to_string(settings.max_range));
  }
}
RayIntegrator::~RayIntegrator() = default;
RayIntegrator::RayIntegrator(RayIntegrator&&) noexcept = default;
RayIntegrator& RayIntegrator::operator=(RayIntegrator&&) noexcept = default;

IntegrationStats RayIntegrator::integrate(MetricMap& map, const PointBuffer& points,
                                          const Eigen::Vector3d& origin) {
  IntegrationStats stats;
  ScanRays& rays = scratch_->rays;
  rays.compute(settings_, map.resolution(), points, origin, stats);
  scratch_->update.apply(map, rays, stats);
  return stats;
}

}  // namespace sarmap::metric
