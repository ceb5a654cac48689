// What one scan's rays say, found without reading or writing the map: the
// first two passes of ray integration (ray_integrator.hpp tells the whole
// story). Pass 1 finds the distinct voxels the points end in, with their
// class observations, and one ray per end voxel (or per point when not
// discretising); pass 2 walks the rays and sets a bit for every voxel they
// cross in per-thread block masks, and (into a dense grid) the hits are
// listed by the grid's blocks for the update. Because nothing here touches the map,
// one scan's ScanRays can be computed while the scan before is still being
// written into the map (RayIntegrator::trace and apply).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <tbb/enumerable_thread_specific.h>

#include "engine/core/point_buffer.hpp"
#include "engine/metric/end_voxel_groups.hpp"
#include "engine/core/flat_key_index.hpp"
#include "engine/core/huge_page_allocator.hpp"
#include "engine/metric/grid_hit_list.hpp"
#include "engine/metric/integration_settings.hpp"
#include "kernels/ray_marking.hpp"

namespace sarmap::metric {

using BlockMask = std::array<std::uint64_t, kernels::kMarkBlockWords>;

// One thread's misses for one scan: either a mask per block of the scan's
// box (dense, no look-up per block) or a mask per block its rays crossed,
// found through the thread's own key index. Walks share nothing.
struct ThreadMisses {
  // Used by a hashed walk only, and grown there: a dense walk never touches it.
  FlatKeyIndex blocks{16};
  std::vector<BlockMask> miss;          // per entry of blocks
  std::uint64_t* miss_words = nullptr;  // miss.data() as words, for the marking kernel
  std::size_t visits = 0;
  std::size_t rays = 0;  // rays walked (counted by the walk that runs beside the merge)
  // A mask per block of the scan's box; valid for this scan only when
  // dense_in_use (a thread that walked no ray has none). All zero between
  // scans: ScanUpdate clears the blocks it reads, while they are in cache,
  // instead of another pass over the whole grid before each walk.
  HugePageVector<std::uint64_t> dense;
  bool dense_in_use = false;

  void clear();
  // The box's grid over this thread's words, zeroed and sized to the box the
  // first time this scan asks (the walks of one scan share one box).
  kernels::DenseMaskGrid dense_grid(const kernels::DenseMaskGrid& box);
  // Bytes held (key index, masks and dense grid, by capacity).
  std::size_t memory_bytes() const;
  // kernels::BlockMaskSink::block_index: the mask of a block, created empty.
  static std::uint32_t block_index(void* self, std::int32_t bx, std::int32_t by, std::int32_t bz);
};

// A ray's end in voxel units.
struct RayEnd {
  double x, y, z;
};

class ScanRays {
 public:
  // Passes 1 and 2 for the scan's points (world frame) seen from origin, at
  // the map's resolution (metres); adds points_in, points_rejected,
  // end_voxels, rays, voxel_visits and the dense counts to stats. Throws
  // sarmap::Error for an origin beyond the map limits (OutOfRange) or a
  // label that is not a class id (InvalidData). Parallel over the calling
  // thread's oneTBB arena; the results do not depend on its thread count.
  // When discretising into a dense grid (the common case), pass 1's serial
  // merge runs beside the walks of the rays it has finished.
  void compute(const IntegratorSettings& settings, double resolution, const PointBuffer& points,
               const Eigen::Vector3d& origin, IntegrationStats& stats);

  // The distinct end voxels and their observations, in a fixed order.
  const EndVoxelGroups& ends() const { return ends_; }
  // Per end voxel: 1 when it is a hit (within the max range).
  const HugePageVector<std::uint8_t>& end_is_hit() const { return end_is_hit_; }
  // The grid the walk marked into, when the scan's box was small enough;
  // else the threads' masks are per block through their key indices.
  const std::optional<kernels::DenseMaskGrid>& dense_box() const { return dense_box_; }
  // With a dense box, the hits listed by its blocks (unless one lay outside
  // it: then not listed()).
  const GridHitList& hits_by_grid_block() const { return grid_hits_; }
  // Every thread's misses (their union is the scan's). Non-const for
  // ScanUpdate, which clears the dense grids as it merges them and then
  // calls dense_grids_cleared().
  tbb::enumerable_thread_specific<ThreadMisses>& threads() { return threads_; }
  void dense_grids_cleared() { dense_dirty_ = false; }

  // Bytes held between scans: every table and buffer of both passes and
  // every thread's masks, by capacity. Not thread-safe with compute().
  std::size_t memory_bytes() const;

 private:
  // Pass 1's work on one fixed stretch of points besides its end-voxel
  // groups (local_groups_): (when not discretising) their rays in point
  // order, the points rejected, and the first point with a bad label.
  struct PointChunk {
    std::vector<RayEnd> rays;
    std::size_t rejected = 0;
    std::size_t bad_label = kNoBadLabel;
    static constexpr std::size_t kNoBadLabel = ~std::size_t{0};
  };

  std::span<const LocalEndGroups> group_points(const IntegratorSettings& settings, double resolution,
                                               const PointBuffer& points, IntegrationStats& stats);
  // Pass 1's merge with pass 2 beside it, into the dense grid dense_box_.
  void merge_while_walking(const IntegratorSettings& settings, double resolution,
                           std::span<const LocalEndGroups> stretches, IntegrationStats& stats);
  // Adds the merged end voxels' counts to stats.
  void count_ends(IntegrationStats& stats) const;
  // Pass 2 after the whole of pass 1.
  void walk(const IntegratorSettings& settings, IntegrationStats& stats);

  RayEnd origin_{};  // the scan's sensor origin in voxel units, from compute()
  std::vector<PointChunk> chunks_;
  std::vector<LocalEndGroups> local_groups_;  // per chunk
  EndVoxelGroups ends_;
  HugePageVector<std::uint8_t> end_is_hit_;
  HugePageVector<RayEnd> rays_;
  std::optional<kernels::DenseMaskGrid> dense_box_;
  GridHitList grid_hits_;
  // Set from a dense walk until ScanUpdate has cleared the grids; if still
  // set at the next compute() (the scan was never applied, or a walk threw),
  // the grids are zeroed there.
  bool dense_dirty_ = false;
  tbb::enumerable_thread_specific<ThreadMisses> threads_;
};

}  // namespace sarmap::metric
