// What ray integration can be told (IntegratorSettings) and what it reports
// per scan (IntegrationStats); the integrator itself is ray_integrator.hpp.
#pragma once

#include <cstddef>

namespace sarmap::metric {

struct IntegratorSettings {
  // Rays longer than this (metres) are cut here and mark misses only; 0 = no limit.
  double max_range = 0.0;
  // When false, points beyond max_range are ignored instead of clearing space
  // up to it (true suits LiDAR no-returns reported at or beyond max range).
  bool clear_beyond_max_range = true;
  // Cast one ray per distinct end voxel, to the voxel centre (OctoMap's
  // insertPointCloud with discretize=true); false casts to every true end point.
  bool discretize = true;
  // Use per-class score channels named after the classes (probabilities) when
  // the buffer has all six; otherwise the hard labels.
  bool use_scores = true;
  // The free-space walk marks into a dense grid of block masks over the
  // scan's box (origin and ray ends) when the box has at most this many
  // blocks (64 bytes each, per thread); beyond it, into blocks found through
  // a hash table, which is slower per voxel but needs memory only where rays
  // pass. 0 = always the hash table. Both give the same map.
  std::size_t dense_walk_max_blocks = std::size_t{1} << 17;
  // Likewise the end-voxel dedupe uses a dense table (4 bytes per voxel,
  // kept between scans) over the box of the scan's end voxels when it has at
  // most this many voxels, else a hash table; 0 = always the hash table.
  std::size_t dense_dedupe_max_cells = std::size_t{1} << 24;
};

// Per-scan figures; summed over scans by operator+=.
struct IntegrationStats {
  std::size_t points_in = 0;
  // Non-finite or beyond +-10 km: rejected and counted, never wrapped.
  std::size_t points_rejected = 0;
  std::size_t end_voxels = 0;    // distinct voxels holding a usable point
  std::size_t rays = 0;          // rays cast (cut rays included)
  std::size_t voxel_visits = 0;  // voxels walked by all rays, repeats included
  std::size_t hits = 0;          // voxels updated as occupied this scan
  std::size_t misses = 0;        // voxels updated as free this scan
  std::size_t blocks_created = 0;
  // Scans whose walk marked into the dense grid, and whose dedupe used the
  // dense table (the others used hash tables; see IntegratorSettings).
  std::size_t dense_walks = 0;
  std::size_t dense_dedupes = 0;

  IntegrationStats& operator+=(const IntegrationStats& o);
};

}  // namespace sarmap::metric
