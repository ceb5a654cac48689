// One scan in four passes: (1) the distinct end voxels with their class
// observations (keys by a vector kernel, kernels/voxel_keys.hpp; grouped
// locally in parallel, merged in order: end_voxel_groups.hpp), and one ray
// per end voxel;
// (2) parallel DDA walks that only set "miss" bits in per-thread masks (no
// locks, no atomics, no map access) — a dense grid of block masks over the
// scan's box when it is small enough, which needs no look-up per block, else
// masks found through a per-thread hash table; (3) a serial merge of the
// masks (OR, so the union does not depend on which thread walked which ray),
// block creation in sorted key order, hit bits that override misses, and
// the hits listed by block; (4) parallel updates, one block per task (its
// misses, then its hits), so every voxel is written exactly once by one thread.
#include "engine/metric/ray_integrator.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/metric/end_voxel_groups.hpp"
#include "engine/metric/flat_key_index.hpp"
#include "kernels/ray_marking.hpp"
#include "kernels/simd_level.hpp"
#include "kernels/voxel_keys.hpp"

namespace sarmap::metric {

namespace {

using BlockMask = std::array<std::uint64_t, kBlockVoxels / 64>;

// One thread's misses for one scan: a mask per block its rays crossed, found
// through the thread's own key index, so walks share nothing.
struct ThreadRays {
  FlatKeyIndex blocks{4096};
  std::vector<BlockMask> miss;
  std::uint64_t* miss_words = nullptr;  // miss.data() as words, for the marking kernel
  std::size_t visits = 0;
  // The dense alternative: a mask per block of the scan's box; valid for
  // this scan only when dense_in_use (a thread that walked no ray has none).
  std::vector<std::uint64_t> dense;
  bool dense_in_use = false;

  void clear() {
    blocks.clear();
    miss.clear();
    miss_words = nullptr;
    visits = 0;
    dense_in_use = false;
  }
  // kernels::BlockMaskSink::block_index: the mask of a block, created empty.
  static std::uint32_t block_index(void* self, std::int32_t bx, std::int32_t by, std::int32_t bz) {
    auto& t = *static_cast<ThreadRays*>(self);
    const std::uint32_t b = t.blocks.find_or_insert(pack(bx, by, bz));
    if (b == t.miss.size()) {
      t.miss.emplace_back();
      t.miss_words = t.miss.front().data();
    }
    return b;
  }
};
static_assert(kernels::kVoxelKeyBits == kPackBits && kernels::kVoxelKeyOffset == kPackOffset,
              "the key kernel packs voxels as pack() does");
static_assert(kernels::kMarkBlockShift == kBlockShift && kernels::kMarkBlockWords == BlockMask{}.size(),
              "the marking kernel's blocks are the map's blocks");

struct RayEnd {
  double x, y, z;  // voxel units
};
static_assert(sizeof(RayEnd) == 3 * sizeof(double), "ray ends are read as packed xyz triples");

}  // namespace

namespace {

// Pass 1's work on one stretch of the scan's points besides their end-voxel
// groups (Scratch::local_groups): (when not discretising) their rays in
// point order, and the points rejected.
struct PointChunk {
  std::vector<RayEnd> rays;
  std::size_t rejected = 0;

  void clear() {
    rays.clear();
    rejected = 0;
  }
};

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
std::optional<kernels::DenseMaskGrid> scan_block_box(const double start[3], const std::vector<RayEnd>& ends,
                                                     std::size_t max_blocks) {
  max_blocks = std::min(max_blocks, kDenseGridMaxBlocks - 1);
  if (max_blocks == 0 || ends.empty()) return std::nullopt;
  // Ray ends are within the map limits (+-10 km, at 1 cm at most 250,001
  // blocks per axis), so the product of the extents fits a size_t.
  const kernels::DenseMaskGrid grid = kernels::dense_grid_covering(start, &ends.front().x, ends.size());
  if (kernels::dense_grid_blocks(grid) > max_blocks) return std::nullopt;
  return grid;
}

}  // namespace

struct RayIntegrator::Scratch {
  std::vector<PointChunk> chunks;
  std::vector<LocalEndGroups> local_groups;  // per chunk
  EndVoxelGroups ends;
  std::vector<std::uint8_t> end_in_range;  // per distinct end voxel: is it a hit
  std::vector<RayEnd> ray_ends;
  tbb::enumerable_thread_specific<ThreadRays> threads;
  FlatKeyIndex merged{16384};
  std::vector<BlockMask> merged_miss, merged_hit;
  std::vector<std::uint32_t> order;
  std::vector<MetricMap::Blocks::Block*> block_of_index;
  // In-range end voxels (hits) by merged block: hit_list[hit_start[b] ..
  // hit_start[b + 1]) are block b's; hit_block and hit_cursor build it.
  std::vector<std::uint32_t> hit_list, hit_block, hit_cursor, hit_start;
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
  Scratch& s = *scratch_;
  IntegrationStats stats;
  stats.points_in = points.size();
  if (!within_map_limits(origin.x(), origin.y(), origin.z())) {
    throw Error(ErrorCode::OutOfRange, "ray integrator: sensor origin (" + std::to_string(origin.x()) + ", " +
                                           std::to_string(origin.y()) + ", " + std::to_string(origin.z()) +
                                           ") is beyond the map limits of +-10 km or not finite");
  }
  if (points.has_labels()) {
    const auto labels = points.labels();
    for (std::size_t i = 0; i < labels.size(); ++i) {
      if (labels[i] >= kClassCount) {
        throw Error(ErrorCode::InvalidData, "ray integrator: point " + std::to_string(i) + " has label " +
                                                std::to_string(labels[i]) + "; class ids are 0..5");
      }
    }
  }

  const double inv_res = map.inv_resolution();
  const double res = map.resolution();
  const RayEnd o{origin.x() * inv_res, origin.y() * inv_res, origin.z() * inv_res};
  const double max_range = settings_.max_range;
  // Range is measured in voxel units to stay in one coordinate system.
  const double max_range_v = max_range * inv_res;

  // Pass 1: distinct end voxels, their observations, and the rays: keys,
  // local groups and rays in parallel over fixed chunks of points (rays
  // concatenated in chunk order), then the groups merged in chunk order, so
  // nothing depends on the thread count.
  s.end_in_range.clear();
  s.ray_ends.clear();
  const auto xs = points.x(), ys = points.y(), zs = points.z();
  const auto beyond = [&](double dx, double dy, double dz) {
    return max_range > 0 && std::sqrt(dx * dx + dy * dy + dz * dz) * res > max_range;
  };
  // The ray to end: end itself when within range (a hit), else cut at the
  // max range (misses only) or, when cutting is off, none.
  enum class RayKind : std::uint8_t { Hit, Cut, None };
  const auto ray_to = [&](const RayEnd& end, RayEnd& ray) -> RayKind {
    const double dx = end.x - o.x, dy = end.y - o.y, dz = end.z - o.z;
    if (!beyond(dx, dy, dz)) {
      ray = end;
      return RayKind::Hit;
    }
    if (!settings_.clear_beyond_max_range) return RayKind::None;
    const double f = max_range_v / std::sqrt(dx * dx + dy * dy + dz * dz);
    ray = {o.x + dx * f, o.y + dy * f, o.z + dz * f};
    return RayKind::Cut;
  };
  // Appends the ray to end, if any; returns whether end itself is a hit.
  const auto add_ray = [&](std::vector<RayEnd>& rays, const RayEnd& end) -> bool {
    RayEnd ray;
    const RayKind kind = ray_to(end, ray);
    if (kind != RayKind::None) rays.push_back(ray);
    return kind == RayKind::Hit;
  };
  const std::size_t chunk_count = (points.size() + kChunkPoints - 1) / kChunkPoints;
  if (s.chunks.size() < chunk_count) s.chunks.resize(chunk_count);
  if (s.local_groups.size() < chunk_count) s.local_groups.resize(chunk_count);
  const ClassSource class_source = ClassSource::of(points, settings_.use_scores);
  const kernels::SimdLevel level = kernels::active_simd_level();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunk_count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    std::uint64_t keys[kKeyBatch];
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      PointChunk& chunk = s.chunks[c];
      LocalEndGroups& groups = s.local_groups[c];
      chunk.clear();
      groups.clear();
      const std::size_t end = std::min(points.size(), (c + 1) * kChunkPoints);
      for (std::size_t first = c * kChunkPoints; first < end; first += kKeyBatch) {
        const std::size_t n = std::min(kKeyBatch, end - first);
        kernels::voxel_keys(&xs[first], &ys[first], &zs[first], n, inv_res, kMaxCoordinate, keys, level);
        for (std::size_t j = 0; j < n; ++j) {
          if (keys[j] == kernels::kRejectedVoxelKey) {  // non-finite or beyond the map limits
            ++chunk.rejected;
            continue;
          }
          const std::size_t i = first + j;
          // Every point casts its own ray unless discretising; only those in range are hits.
          if (!settings_.discretize &&
              !add_ray(chunk.rays, {double{xs[i]} * inv_res, double{ys[i]} * inv_res, double{zs[i]} * inv_res})) {
            continue;
          }
          groups.add(keys[j], i, class_source);
        }
      }
    }
  });
  for (std::size_t c = 0; c < chunk_count; ++c) {
    const PointChunk& chunk = s.chunks[c];
    stats.points_rejected += chunk.rejected;
    s.ray_ends.insert(s.ray_ends.end(), chunk.rays.begin(), chunk.rays.end());
  }
  s.ends.merge(std::span<const LocalEndGroups>(s.local_groups.data(), chunk_count), settings_.dense_dedupe_max_cells);
  const std::vector<VoxelKey>& end_keys = s.ends.keys();
  stats.dense_dedupes = s.ends.used_dense_table() ? 1 : 0;
  stats.end_voxels = end_keys.size();
  s.end_in_range.assign(end_keys.size(), 1);
  if (settings_.discretize) {
    // One ray per end voxel, to its centre, computed in parallel (serially,
    // this loop was a few per cent of a 2-thread run, the other thread idle),
    // then the voxels without a ray (beyond range, not clearing) squeezed out.
    s.ray_ends.resize(end_keys.size());
    std::vector<RayEnd>& rays = s.ray_ends;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, end_keys.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t u = range.begin(); u != range.end(); ++u) {
                          const VoxelKey& k = end_keys[u];
                          const RayKind kind = ray_to({k.x + 0.5, k.y + 0.5, k.z + 0.5}, rays[u]);
                          s.end_in_range[u] = kind == RayKind::Hit ? 1 : 0;
                          // A NaN x marks "no ray" for the squeeze below.
                          if (kind == RayKind::None) rays[u].x = std::numeric_limits<double>::quiet_NaN();
                        }
                      });
    if (!settings_.clear_beyond_max_range) {
      std::erase_if(rays, [](const RayEnd& ray) { return std::isnan(ray.x); });
    }
  }
  stats.rays = s.ray_ends.size();

  // Pass 2: parallel walks into per-thread miss masks (several rays per step
  // in SIMD lanes where the CPU has AVX2 or AVX-512).
  for (ThreadRays& t : s.threads) t.clear();
  const double start[3] = {o.x, o.y, o.z};
  const std::optional<kernels::DenseMaskGrid> box =
      scan_block_box(start, s.ray_ends, settings_.dense_walk_max_blocks);
  stats.dense_walks = box ? 1 : 0;
  if (box) {
    const std::size_t words = kernels::kMarkBlockWords * kernels::dense_grid_blocks(*box);
    // About 16-32 ranges per scan, of at least 256 rays: the SIMD lanes
    // drain at the end of every call, so short calls leave lanes idle (64
    // rays measured 4-8 % slower at 1 thread), but with fewer than about ten
    // ranges two threads got uneven shares (auto_partitioner made 5-8 of
    // 630-1024 rays at 0.05 m).
    const std::size_t grain = std::max<std::size_t>(512, (s.ray_ends.size() + 15) / 16);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.ray_ends.size(), grain),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        ThreadRays& t = s.threads.local();
                        if (!t.dense_in_use) {
                          t.dense.assign(words, 0);
                          t.dense_in_use = true;
                        }
                        kernels::DenseMaskGrid grid = *box;
                        grid.words = t.dense.data();
                        t.visits += kernels::mark_ray_cells_dense(start, &s.ray_ends[range.begin()].x, range.size(),
                                                                  grid, level);
                      }, tbb::simple_partitioner());
  } else {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.ray_ends.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        ThreadRays& t = s.threads.local();
                        const kernels::BlockMaskSink sink{&ThreadRays::block_index, &t, &t.miss_words};
                        t.visits += kernels::mark_ray_cells(start, &s.ray_ends[range.begin()].x, range.size(), sink,
                                                            level);
                      });
  }

  // Pass 3: merge, add hits, create blocks in sorted order.
  s.merged.clear();
  s.merged_miss.clear();
  const auto merged_index = [&](std::uint64_t word) {
    const std::uint32_t b = s.merged.find_or_insert(word);
    if (b == s.merged_miss.size()) s.merged_miss.emplace_back();
    return b;
  };
  for (ThreadRays& t : s.threads) {
    stats.voxel_visits += t.visits;
    const auto& keys = t.blocks.keys();
    for (std::size_t b = 0; b < keys.size(); ++b) {
      BlockMask& m = s.merged_miss[merged_index(keys[b])];
      for (std::size_t w = 0; w < m.size(); ++w) m[w] |= t.miss[b][w];
    }
  }
  if (box) {
    // The box's blocks in grid order; only those some ray crossed.
    std::size_t g = 0;
    for (std::int32_t k = 0; k < box->blocks[2]; ++k) {
      for (std::int32_t j = 0; j < box->blocks[1]; ++j) {
        for (std::int32_t i = 0; i < box->blocks[0]; ++i, ++g) {
          BlockMask m{};
          std::uint64_t any = 0;
          for (const ThreadRays& t : s.threads) {
            if (!t.dense_in_use) continue;
            for (std::size_t w = 0; w < m.size(); ++w) m[w] |= t.dense[g * m.size() + w];
          }
          for (std::uint64_t w : m) any |= w;
          if (any == 0) continue;
          s.merged_miss[merged_index(pack(box->first_block[0] + i, box->first_block[1] + j, box->first_block[2] + k))] = m;
        }
      }
    }
  }
  // Hits: each in-range end voxel's block (created if no ray crossed it),
  // then the hits listed by block (a counting sort), so that pass 4 updates
  // a block's misses and hits in one task without looking blocks up again.
  s.hit_block.clear();
  for (std::uint32_t u = 0; u < end_keys.size(); ++u) {
    if (s.end_in_range[u]) s.hit_block.push_back(merged_index(pack(block_of(end_keys[u]))));
  }
  s.merged_hit.assign(s.merged_miss.size(), BlockMask{});
  s.hit_start.assign(s.merged_miss.size() + 1, 0);
  for (std::uint32_t b : s.hit_block) ++s.hit_start[b + 1];
  for (std::size_t b = 1; b < s.hit_start.size(); ++b) s.hit_start[b] += s.hit_start[b - 1];
  s.hit_list.resize(s.hit_block.size());
  {
    std::size_t h = 0;
    s.hit_cursor.assign(s.hit_start.begin(), s.hit_start.end() - 1);
    for (std::uint32_t u = 0; u < end_keys.size(); ++u) {
      if (!s.end_in_range[u]) continue;
      const std::uint32_t b = s.hit_block[h++];
      s.hit_list[s.hit_cursor[b]++] = u;
      const int l = local_index(end_keys[u]);
      s.merged_hit[b][l >> 6] |= std::uint64_t{1} << (l & 63);
    }
  }
  const auto& merged_keys = s.merged.keys();
  s.order.resize(merged_keys.size());
  for (std::uint32_t b = 0; b < s.order.size(); ++b) s.order[b] = b;
  std::sort(s.order.begin(), s.order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return merged_keys[a] < merged_keys[b]; });
  auto& blocks = map.blocks();
  const std::size_t blocks_before = blocks.block_count();
  s.block_of_index.resize(merged_keys.size());
  for (std::uint32_t b : s.order) s.block_of_index[b] = &blocks.find_or_create(unpack_block(merged_keys[b]));
  stats.blocks_created = blocks.block_count() - blocks_before;
  for (std::size_t b = 0; b < merged_keys.size(); ++b) {
    for (std::size_t w = 0; w < BlockMask{}.size(); ++w) {
      stats.misses += static_cast<std::size_t>(std::popcount(s.merged_miss[b][w] & ~s.merged_hit[b][w]));
    }
  }
  stats.hits = s.hit_list.size();

  // Pass 4: parallel updates, one block per task (its misses, then its
  // hits), so each voxel belongs to exactly one task.
  const OccupancyModel& occ = map.occupancy();
  const LabelFusion& fusion = map.fusion();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, merged_keys.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t b = range.begin(); b != range.end(); ++b) {
                        auto& voxels = s.block_of_index[b]->voxels;
                        for (std::size_t w = 0; w < BlockMask{}.size(); ++w) {
                          std::uint64_t bits = s.merged_miss[b][w] & ~s.merged_hit[b][w];
                          while (bits) {
                            SemanticVoxel& v = voxels[w * 64 + static_cast<std::size_t>(std::countr_zero(bits))];
                            bits &= bits - 1;
                            v.log_odds = occ.add(v.log_odds, occ.miss());
                            if (occ.state(v.log_odds) == VoxelState::Free) fusion.decay(v.evidence);
                          }
                        }
                        for (std::size_t h = s.hit_start[b]; h != s.hit_start[b + 1]; ++h) {
                          const std::uint32_t u = s.hit_list[h];
                          SemanticVoxel& v = voxels[local_index(end_keys[u])];
                          v.log_odds = occ.add(v.log_odds, occ.hit());
                          fusion.observe(v.evidence, s.ends.observations()[u]);
                        }
                      }
                    });
  return stats;
}

}  // namespace sarmap::metric
