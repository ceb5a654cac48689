#include "engine/metric/scan_rays.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <span>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "kernels/simd_level.hpp"
#include "kernels/voxel_keys.hpp"

namespace sarmap::metric {

static_assert(kernels::kVoxelKeyBits == kPackBits && kernels::kVoxelKeyOffset == kPackOffset,
              "the key kernel packs voxels as pack() does");
static_assert(kernels::kMarkBlockShift == kBlockShift && kernels::kMarkBlockWords * 64 == kBlockVoxels,
              "the marking kernel's blocks are the map's blocks");
static_assert(sizeof(RayEnd) == 3 * sizeof(double), "ray ends are read as packed xyz triples");

void ThreadMisses::clear() {
  blocks.clear();
  miss.clear();
  miss_words = nullptr;
  visits = 0;
  rays = 0;
  dense_in_use = false;
}

std::size_t ThreadMisses::memory_bytes() const {
  return blocks.memory_bytes() + capacity_bytes(miss) + capacity_bytes(dense);
}

kernels::DenseMaskGrid ThreadMisses::dense_grid(const kernels::DenseMaskGrid& box) {
  if (!dense_in_use) {
    const std::size_t words = kernels::kMarkBlockWords * kernels::dense_grid_blocks(box);
    if (dense.size() < words) {  // all zero already up to size()
      resize_in_whole_huge_pages(dense, words);
    }
    dense_in_use = true;
  }
  kernels::DenseMaskGrid grid = box;
  grid.words = dense.data();
  return grid;
}

std::uint32_t ThreadMisses::block_index(void* self, std::int32_t bx, std::int32_t by, std::int32_t bz) {
  auto& t = *static_cast<ThreadMisses*>(self);
  const std::uint32_t b = t.blocks.find_or_insert(pack(bx, by, bz));
  if (b == t.miss.size()) {
    t.miss.emplace_back();
    t.miss_words = t.miss.front().data();
  }
  return b;
}

namespace {

// Points per chunk of pass 1's parallel part: fixed, so that the rays are
// concatenated in the same order for any thread count; small enough that a
// 320 x 240 scan makes ten chunks (five of 16384 split 3 : 2 between two
// threads), large enough that few voxels straddle chunks (each such voxel is
// one more group to merge serially).
constexpr std::size_t kChunkPoints = 8192;
// Points whose keys the kernel computes at a time (on the stack, in L1).
constexpr std::size_t kKeyBatch = 512;

// The marking kernel addresses the grid's words with 32-bit indices.
constexpr std::size_t kDenseGridMaxBlocks = (std::size_t{1} << 31) / kernels::kMarkBlockWords;

// The scan's dense mask grid (without words), or nothing when it has more
// than max_blocks blocks.
std::optional<kernels::DenseMaskGrid> scan_block_box(const double start[3], std::span<const RayEnd> ends,
                                                     std::size_t max_blocks) {
  max_blocks = std::min(max_blocks, kDenseGridMaxBlocks - 1);
  if (max_blocks == 0 || ends.empty()) return std::nullopt;
  // Ray ends are within the map limits (+-10 km, at 1 cm at most 250,001
  // blocks per axis), so the product of the extents fits a size_t.
  const kernels::DenseMaskGrid grid = kernels::dense_grid_covering(start, &ends.front().x, ends.size());
  if (kernels::dense_grid_blocks(grid) > max_blocks) return std::nullopt;
  return grid;
}

// The first point of labels[first, end) whose label is not a class id, or end.
std::size_t first_bad_label(std::span<const std::uint8_t> labels, std::size_t first, std::size_t end) {
  // The largest label first: a loop the compiler vectorises, and the
  // labels are then in cache for pass 1's observations.
  std::uint8_t largest = 0;
  for (std::size_t i = first; i < end; ++i) largest = std::max(largest, labels[i]);
  if (largest < kClassCount) return end;
  for (std::size_t i = first; i < end; ++i) {
    if (labels[i] >= kClassCount) return i;
  }
  return end;
}

// The ray to an end (voxel units): the end itself when within range (a
// hit), else cut at the max range (misses only) or, when cutting is off, none.
enum class RayKind : std::uint8_t { Hit, Cut, None };
struct RayCutter {
  RayEnd origin;
  double resolution;
  double max_range;    // metres; 0 = no limit
  double max_range_v;  // the same in voxel units
  bool clear_beyond;

  // Whether the ray to end is a hit (ray_to()'s kind is Hit).
  bool hits(const RayEnd& end) const {
    if (max_range == 0) return true;
    RayEnd unused;
    return ray_to(end, unused) == RayKind::Hit;
  }

  RayKind ray_to(const RayEnd& end, RayEnd& ray) const {
    const double dx = end.x - origin.x, dy = end.y - origin.y, dz = end.z - origin.z;
    const double length_v = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (max_range == 0 || !(length_v * resolution > max_range)) {
      ray = end;
      return RayKind::Hit;
    }
    if (!clear_beyond) return RayKind::None;
    // Cut in voxel units, the ray's own coordinate system.
    const double f = max_range_v / length_v;
    ray = {origin.x + dx * f, origin.y + dy * f, origin.z + dz * f};
    return RayKind::Cut;
  }
};

// The scan's cutter: every pass casts its rays with the same one.
RayCutter cutter_for(const RayEnd& origin, const IntegratorSettings& settings, double resolution) {
  return {origin, resolution, settings.max_range, settings.max_range * (1.0 / resolution),
          settings.clear_beyond_max_range};
}

// Rays per call of the dense walk after the whole of pass 1 (walk()), and
// per claim while the merge goes on (WalkClaims): at least 512 and about 16
// per scan. The SIMD lanes drain at the end of every call, so short calls
// leave lanes idle (64 rays measured slower at 1 thread), but with fewer
// than about ten calls two threads got uneven shares (auto_partitioner made
// too few ranges at 0.05 m). Claims go to one walk per thread as its pieces
// (ClaimedRays), which drains only at its end.
std::size_t walk_grain(std::size_t rays) { return std::max<std::size_t>(512, (rays + 15) / 16); }

// The smallest piece of the walk's last rays (WalkClaims).
constexpr std::size_t kLastPieceMin = 128;

// The end voxels the merge has finished, claimed by the walking threads a
// piece at a time. While the merge goes on, a piece is a whole grain
// (walk_grain), but the very first is taken as soon as the merge has
// finished any, so that the other threads start early; once the merge is
// done the pieces shrink with what is left, down to kLastPieceMin, so that
// the threads run out of rays at about the same time. Which thread walks
// which rays does not change the map: the threads' miss masks are ORed.
class WalkClaims {
 public:
  WalkClaims(std::size_t grain, std::size_t threads)
      : grain_(grain), threads_(std::max<std::size_t>(threads, 1)) {}

  // By the merging thread: the end voxels below n are final (their keys
  // written), and with merge_done() there are no more.
  void finished(std::size_t n) { finished_.store(n, std::memory_order_release); }
  void merge_done(std::size_t n) {
    finished_.store(n, std::memory_order_release);
    done_.store(true, std::memory_order_release);
  }

  // Claims [first, last); false when nothing is to be had now (all claimed,
  // or less than a grain finished while the merge goes on).
  bool claim(std::size_t& first, std::size_t& last) {
    std::size_t at = next_.load(std::memory_order_relaxed);
    while (true) {
      // done_ before finished_: once done, the count read after it is the last.
      const bool done = done_.load(std::memory_order_acquire);
      const std::size_t limit = finished_.load(std::memory_order_acquire);
      if (at >= limit) return false;
      const std::size_t left = limit - at;
      std::size_t piece = 0;
      if (done && threads_ > 1) {
        piece = std::min(left, std::clamp(left / (2 * threads_), kLastPieceMin, grain_));
      } else if (done) {
        piece = std::min(left, grain_);  // alone: nothing to balance
      } else if (at == 0 || left >= grain_) {
        piece = std::min(left, grain_);
      } else {
        return false;
      }
      if (next_.compare_exchange_weak(at, at + piece, std::memory_order_relaxed)) {
        first = at;
        last = at + piece;
        return true;
      }
    }
  }

 private:
  const std::size_t grain_, threads_;
  std::atomic<std::size_t> finished_{0};
  std::atomic<bool> done_{false};
  std::atomic<std::size_t> next_{0};
};

// The rays of the end voxels one thread claims (WalkClaims), handed to the
// dense walk as its pieces (kernels::RayPieces) and cast as it asks for
// them: one walk per thread goes on from claim to claim, its SIMD lanes
// draining only when nothing is left to claim, not at the end of each
// claim. A claim [first, last)'s rays are packed from rays[first] on
// (claims never overlap, so no thread sees another's).
class ClaimedRays {
 public:
  ClaimedRays(WalkClaims& claims, const VoxelKey* keys, const RayCutter& cutter, RayEnd* rays)
      : claims_(claims), keys_(keys), cutter_(cutter), rays_(rays) {}

  // Claims the first piece; false when nothing is to be had now.
  bool claim_first() { return claim(); }
  kernels::RayPieces pieces() { return {&ClaimedRays::next, this}; }
  // Rays cast so far.
  std::size_t cast() const { return cast_; }

 private:
  static bool next(void* self, const double** ends, std::size_t* count) {
    auto& c = *static_cast<ClaimedRays*>(self);
    if (!c.claimed_ && !c.claim()) return false;
    c.claimed_ = false;
    *ends = &c.rays_[c.first_].x;
    *count = c.piece_;
    return true;
  }
  bool claim() {
    std::size_t first = 0, last = 0;
    if (!claims_.claim(first, last)) return false;
    std::size_t n = 0;
    for (std::size_t u = first; u < last; ++u) {
      const VoxelKey& k = keys_[u];
      n += cutter_.ray_to({k.x + 0.5, k.y + 0.5, k.z + 0.5}, rays_[first + n]) == RayKind::None ? 0 : 1;
    }
    first_ = first;
    piece_ = n;
    cast_ += n;
    claimed_ = true;
    return true;
  }

  WalkClaims& claims_;
  const VoxelKey* keys_;
  const RayCutter& cutter_;
  RayEnd* rays_;
  std::size_t first_ = 0, piece_ = 0, cast_ = 0;
  bool claimed_ = false;  // a piece claimed and not yet handed to the walk
};

}  // namespace

void ScanRays::compute(const IntegratorSettings& settings, double resolution, const PointBuffer& points,
                       const Eigen::Vector3d& origin, IntegrationStats& stats) {
  if (!within_map_limits(origin.x(), origin.y(), origin.z())) {
    throw Error(ErrorCode::OutOfRange, "ray integrator: sensor origin (" + std::to_string(origin.x()) + ", " +
                                           std::to_string(origin.y()) + ", " + std::to_string(origin.z()) +
                                           ") is beyond the map limits of +-10 km or not finite");
  }
  stats.points_in += points.size();
  const double inv_res = 1.0 / resolution;
  origin_ = {origin.x() * inv_res, origin.y() * inv_res, origin.z() * inv_res};
  for (ThreadMisses& t : threads_) {
    t.clear();
    if (dense_dirty_) std::fill(t.dense.begin(), t.dense.end(), 0);
  }
  dense_dirty_ = false;
  grid_hits_.clear();
  const std::span<const LocalEndGroups> stretches = group_points(settings, resolution, points, stats);
  const RayCutter cutter = cutter_for(origin_, settings, resolution);
  if (settings.discretize) {
    // Every ray ends in the box of the end voxels or on its way there (cut
    // at the max range), so the grid over that box and the origin holds
    // every walk, and is known before the merge.
    VoxelBox box;
    for (const LocalEndGroups& stretch : stretches) box.add(stretch.box());
    if (!box.empty()) {
      const double start[3] = {origin_.x, origin_.y, origin_.z};
      const std::vector<RayEnd> corners = {{box.lo.x + 0.5, box.lo.y + 0.5, box.lo.z + 0.5},
                                           {box.hi.x + 0.5, box.hi.y + 0.5, box.hi.z + 0.5}};
      dense_box_ = scan_block_box(start, corners, settings.dense_walk_max_blocks);
      if (dense_box_) {
        merge_while_walking(settings, resolution, stretches, stats);
        return;
      }
    }
  }
  ends_.merge(stretches, settings.dense_dedupe_max_cells);
  count_ends(stats);
  reserve_whole_huge_pages(end_is_hit_, ends_.size());
  end_is_hit_.assign(ends_.size(), 1);  // every one a hit until its ray says
  if (settings.discretize) {
    // One ray per end voxel, to its centre, computed in parallel, then the
    // voxels without a ray (beyond range, not clearing) squeezed out.
    const auto& end_keys = ends_.keys();
    resize_in_whole_huge_pages(rays_, end_keys.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, end_keys.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t u = range.begin(); u != range.end(); ++u) {
                          const VoxelKey& k = end_keys[u];
                          const RayKind kind = cutter.ray_to({k.x + 0.5, k.y + 0.5, k.z + 0.5}, rays_[u]);
                          end_is_hit_[u] = kind == RayKind::Hit ? 1 : 0;
                          // A NaN x marks "no ray" for the squeeze below.
                          if (kind == RayKind::None) rays_[u].x = std::numeric_limits<double>::quiet_NaN();
                        }
                      });
    if (!settings.clear_beyond_max_range) {
      std::erase_if(rays_, [](const RayEnd& ray) { return std::isnan(ray.x); });
    }
  }
  stats.rays += rays_.size();
  walk(settings, stats);
}

// Pass 1's parallel part: keys, local groups and (when not discretising)
// rays over fixed chunks of points, so nothing depends on the thread count;
// the rays concatenated in chunk order. Returns the chunks' groups, which
// the merge takes in chunk order.
std::span<const LocalEndGroups> ScanRays::group_points(const IntegratorSettings& settings, double resolution,
                                                       const PointBuffer& points, IntegrationStats& stats) {
  const double inv_res = 1.0 / resolution;
  const RayCutter cutter = cutter_for(origin_, settings, resolution);
  const auto xs = points.x(), ys = points.y(), zs = points.z();
  const std::span<const std::uint8_t> labels =
      points.has_labels() ? points.labels() : std::span<const std::uint8_t>{};
  const std::size_t chunk_count = (points.size() + kChunkPoints - 1) / kChunkPoints;
  if (chunks_.size() < chunk_count) chunks_.resize(chunk_count);
  if (local_groups_.size() < chunk_count) local_groups_.resize(chunk_count);
  const ClassSource class_source = ClassSource::of(points, settings.use_scores);
  const kernels::SimdLevel level = kernels::active_simd_level();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunk_count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    std::uint64_t keys[kKeyBatch];
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      PointChunk& chunk = chunks_[c];
      LocalEndGroups& groups = local_groups_[c];
      chunk.rays.clear();
      chunk.rejected = 0;
      chunk.bad_label = PointChunk::kNoBadLabel;
      groups.clear();
      const std::size_t end = std::min(points.size(), (c + 1) * kChunkPoints);
      if (!labels.empty()) {
        // Checked here, in parallel, rather than before pass 1: a bad label
        // would index past a group's class counts. The error is raised
        // after the loop, before anything touches the map.
        const std::size_t bad = first_bad_label(labels, c * kChunkPoints, end);
        if (bad != end) {
          chunk.bad_label = bad;
          continue;
        }
      }
      for (std::size_t first = c * kChunkPoints; first < end; first += kKeyBatch) {
        const std::size_t n = std::min(kKeyBatch, end - first);
        kernels::voxel_keys(&xs[first], &ys[first], &zs[first], n, inv_res, kMaxCoordinate, keys, level);
        if (settings.discretize && class_source.scores.empty()) {
          // The common case: no ray per point, hard labels or none (add_labelled).
          const std::uint8_t* const batch_labels = labels.empty() ? nullptr : &labels[first];
          for (std::size_t j = 0; j < n; ++j) {
            if (keys[j] == kernels::kRejectedVoxelKey) {  // non-finite or beyond the map limits
              ++chunk.rejected;
              continue;
            }
            groups.add_labelled(keys[j], batch_labels ? batch_labels[j] : std::uint8_t{0});
          }
          continue;
        }
        for (std::size_t j = 0; j < n; ++j) {
          if (keys[j] == kernels::kRejectedVoxelKey) {  // non-finite or beyond the map limits
            ++chunk.rejected;
            continue;
          }
          const std::size_t i = first + j;
          // Every point casts its own ray unless discretising; only those in range are hits.
          if (!settings.discretize) {
            RayEnd ray;
            const RayKind kind =
                cutter.ray_to({double{xs[i]} * inv_res, double{ys[i]} * inv_res, double{zs[i]} * inv_res}, ray);
            if (kind != RayKind::None) chunk.rays.push_back(ray);
            if (kind != RayKind::Hit) continue;
          }
          groups.add(keys[j], i, class_source);
        }
      }
    }
  });
  for (std::size_t c = 0; c < chunk_count; ++c) {
    if (chunks_[c].bad_label == PointChunk::kNoBadLabel) continue;
    const std::size_t i = chunks_[c].bad_label;
    throw Error(ErrorCode::InvalidData, "ray integrator: point " + std::to_string(i) + " has label " +
                                            std::to_string(labels[i]) + "; class ids are 0..5");
  }
  std::size_t ray_count = 0;
  for (std::size_t c = 0; c < chunk_count; ++c) ray_count += chunks_[c].rays.size();
  rays_.clear();
  reserve_whole_huge_pages(rays_, ray_count);
  for (std::size_t c = 0; c < chunk_count; ++c) {
    stats.points_rejected += chunks_[c].rejected;
    rays_.insert(rays_.end(), chunks_[c].rays.begin(), chunks_[c].rays.end());
  }
  return {local_groups_.data(), chunk_count};
}

void ScanRays::count_ends(IntegrationStats& stats) const {
  stats.dense_dedupes += ends_.used_dense_table() ? 1 : 0;
  stats.end_voxels += ends_.size();
}

// The merge of pass 1 and the walk of pass 2 at once: this thread merges the
// chunks' groups in order and starts tasks on the other threads that claim
// the end voxels it has finished (WalkClaims) and cast and walk their rays,
// claim after claim in one walk (ClaimedRays).
// The merge is serial; overlapped so, it no longer leaves the other threads
// idle between the two passes. Once it is done, this thread lists the hits
// and then walks what is left beside them.
void ScanRays::merge_while_walking(const IntegratorSettings& settings, double resolution,
                                   std::span<const LocalEndGroups> stretches, IntegrationStats& stats) {
  const RayCutter cutter = cutter_for(origin_, settings, resolution);
  const double start[3] = {origin_.x, origin_.y, origin_.z};
  const kernels::SimdLevel level = kernels::active_simd_level();
  const kernels::DenseMaskGrid grid = *dense_box_;
  std::size_t most = 0;  // end voxels at most: the chunks' groups
  for (const LocalEndGroups& stretch : stretches) most += stretch.keys().size();
  resize_in_whole_huge_pages(rays_, most);
  dense_dirty_ = true;
  stats.dense_walks += 1;
  const std::size_t grain = walk_grain(most);
  WalkClaims claims(grain, static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()));
  // Walks what it can claim, then leaves the rest to later tasks (or to
  // this thread once the merge is done).
  const auto walk_claimed = [&](const VoxelKey* keys) {
    ClaimedRays claimed(claims, keys, cutter, rays_.data());
    if (!claimed.claim_first()) return;
    ThreadMisses& t = threads_.local();
    t.visits += kernels::mark_ray_pieces_dense(start, claimed.pieces(), t.dense_grid(grid), level);
    t.rays += claimed.cast();
  };
  tbb::task_group walking;
  std::size_t handed = 0;  // end voxels finished when a task was last started
  const auto hand_on = [&] {
    const VoxelKey* keys = ends_.keys().data();  // stays put until the next merge
    walking.run([&walk_claimed, keys] { walk_claimed(keys); });
  };
  try {
    ends_.merge(stretches, settings.dense_dedupe_max_cells, [&](std::size_t final_groups) {
      claims.finished(final_groups);
      if (final_groups > 0 && (handed == 0 || final_groups - handed >= grain)) {
        hand_on();
        handed = final_groups;
      }
    });
    claims.merge_done(ends_.size());
    hand_on();
    // While the last rays are walked: which ends are hits, listed by grid
    // block, so that the update's serial part need not list them.
    resize_in_whole_huge_pages(end_is_hit_, ends_.size());
    const auto& keys = ends_.keys();
    for (std::size_t u = 0; u < keys.size(); ++u) {
      const VoxelKey& k = keys[u];
      end_is_hit_[u] = cutter.hits({k.x + 0.5, k.y + 0.5, k.z + 0.5}) ? 1 : 0;
    }
    grid_hits_.build(grid, keys, end_is_hit_);
    walk_claimed(keys.data());
  } catch (...) {
    walking.wait();  // the tasks read this frame's locals
    throw;
  }
  walking.wait();
  count_ends(stats);
  for (const ThreadMisses& t : threads_) {
    stats.rays += t.rays;
    stats.voxel_visits += t.visits;
  }
}

// Pass 2 after the whole of pass 1 (rays per point, or a box too large for
// a dense grid): parallel walks into per-thread miss masks (several rays per
// step in SIMD lanes where the CPU has AVX2 or AVX-512).
void ScanRays::walk(const IntegratorSettings& settings, IntegrationStats& stats) {
  const RayEnd& o = origin_;
  const double start[3] = {o.x, o.y, o.z};
  const kernels::SimdLevel level = kernels::active_simd_level();
  dense_box_ = scan_block_box(start, rays_, settings.dense_walk_max_blocks);
  stats.dense_walks += dense_box_ ? 1 : 0;
  if (dense_box_) {
    dense_dirty_ = true;
    const std::size_t grain = walk_grain(rays_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays_.size(), grain),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        ThreadMisses& t = threads_.local();
                        t.visits += kernels::mark_ray_cells_dense(start, &rays_[range.begin()].x, range.size(),
                                                                  t.dense_grid(*dense_box_), level);
                      }, tbb::simple_partitioner());
    grid_hits_.build(*dense_box_, ends_.keys(), end_is_hit_);
  } else {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays_.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        ThreadMisses& t = threads_.local();
                        const kernels::BlockMaskSink sink{&ThreadMisses::block_index, &t, &t.miss_words};
                        t.visits += kernels::mark_ray_cells(start, &rays_[range.begin()].x, range.size(), sink,
                                                            level);
                      });
  }
  for (const ThreadMisses& t : threads_) stats.voxel_visits += t.visits;
}

std::size_t ScanRays::memory_bytes() const {
  std::size_t bytes = capacity_bytes(chunks_) + capacity_bytes(local_groups_) + ends_.memory_bytes() +
                      capacity_bytes(end_is_hit_) + capacity_bytes(rays_) + grid_hits_.memory_bytes();
  for (const PointChunk& c : chunks_) bytes += capacity_bytes(c.rays);
  for (const LocalEndGroups& g : local_groups_) bytes += g.memory_bytes();
  for (const ThreadMisses& t : threads_) bytes += sizeof(ThreadMisses) + t.memory_bytes();
  return bytes;
}

}  // namespace sarmap::metric
