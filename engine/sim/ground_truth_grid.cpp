#include "engine/sim/ground_truth_grid.hpp"

#include <algorithm>
#include <atomic>
#include <limits>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/core/error.hpp"
#include "engine/sim/simulator.hpp"

namespace sarmap::sim {
namespace {

// A convex polygon; a triangle clipped by six planes has at most nine corners.
struct Polygon {
  std::array<Eigen::Vector3d, 12> v;
  int n = 0;
};

// Keeps the part of `in` on the inner side of the plane coord[axis] = bound.
void clip(const Polygon& in, int axis, double bound, bool keep_below, Polygon& out) {
  out.n = 0;
  for (int i = 0; i < in.n; ++i) {
    const Eigen::Vector3d& a = in.v[static_cast<std::size_t>(i)];
    const Eigen::Vector3d& b = in.v[static_cast<std::size_t>((i + 1) % in.n)];
    const double da = keep_below ? bound - a[axis] : a[axis] - bound;
    const double db = keep_below ? bound - b[axis] : b[axis] - bound;
    if (da >= 0) out.v[static_cast<std::size_t>(out.n++)] = a;
    if ((da >= 0) != (db >= 0)) {
      const double s = da / (da - db);
      Eigen::Vector3d p = a + s * (b - a);
      p[axis] = bound;  // exactly on the plane, whatever the rounding
      out.v[static_cast<std::size_t>(out.n++)] = p;
    }
  }
}

double area(const Polygon& p) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = 1; i + 1 < p.n; ++i) {
    sum += (p.v[static_cast<std::size_t>(i)] - p.v[0]).cross(p.v[static_cast<std::size_t>(i + 1)] - p.v[0]);
  }
  return 0.5 * sum.norm();
}

// Within this fraction of a voxel, a flat polygon counts as lying on a voxel
// face (float vertices put 0.05 at 0.05000000075).
constexpr double kOnFace = 1e-6;

struct SurfaceSplitter {
  double resolution;
  ClassId label;
  OccupiedVoxelMap& out;
  double min_area;

  // Cuts the polygon into slabs along `axis`, then recurses on the next axis.
  void split(const Polygon& p, int axis, std::array<std::int32_t, 3> key, double weight = 1.0) {
    if (axis == 3) {
      const double a = weight * area(p);
      if (a > weight * min_area) out[{key[0], key[1], key[2]}].area[static_cast<std::size_t>(label)] += a;
      return;
    }
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int i = 0; i < p.n; ++i) {
      lo = std::min(lo, p.v[static_cast<std::size_t>(i)][axis]);
      hi = std::max(hi, p.v[static_cast<std::size_t>(i)][axis]);
    }
    const auto k0 = static_cast<std::int32_t>(std::floor(lo / resolution));
    const auto k1 = static_cast<std::int32_t>(std::floor(hi / resolution));
    if (hi - lo <= 1e-9 * resolution) {
      // Flat along this axis: no clipping (it would count the polygon once
      // per side of a plane it lies in). Lying on a voxel face, it touches
      // the voxels on both sides, and sensor points on it fall on both sides.
      const double at = 0.5 * (lo + hi) / resolution;
      const double face = std::round(at);
      if (std::abs(at - face) < kOnFace) {
        // Half the area on each side keeps the total area exact.
        key[static_cast<std::size_t>(axis)] = static_cast<std::int32_t>(face) - 1;
        split(p, axis + 1, key, 0.5 * weight);
        key[static_cast<std::size_t>(axis)] = static_cast<std::int32_t>(face);
        split(p, axis + 1, key, 0.5 * weight);
      } else {
        key[static_cast<std::size_t>(axis)] = static_cast<std::int32_t>(std::floor(at));
        split(p, axis + 1, key, weight);
      }
      return;
    }
    if (k0 == k1) {
      key[static_cast<std::size_t>(axis)] = k0;
      split(p, axis + 1, key, weight);
      return;
    }
    Polygon below, slab;
    for (std::int32_t k = k0; k <= k1; ++k) {
      clip(p, axis, k * resolution, false, below);
      if (below.n < 3) continue;
      clip(below, axis, (k + 1) * resolution, true, slab);
      if (slab.n < 3) continue;
      key[static_cast<std::size_t>(axis)] = k;
      split(slab, axis + 1, key, weight);
    }
  }
};

void update_labels(OccupiedVoxelMap& map) {
  for (auto& [key, voxel] : map) {
    std::size_t best = 0;
    for (std::size_t c = 1; c < kClassCount; ++c) {
      if (voxel.area[c] > voxel.area[best]) best = c;
    }
    voxel.label = static_cast<ClassId>(best);
  }
}

// One bit per voxel of a box of keys, set from many threads at once.
class DenseVoxelBits {
 public:
  DenseVoxelBits(VoxelKey lo, VoxelKey hi) : lo_(lo), hi_(hi) {
    nx_ = static_cast<std::int64_t>(hi.x) - lo.x + 1;
    ny_ = static_cast<std::int64_t>(hi.y) - lo.y + 1;
    const std::int64_t nz = static_cast<std::int64_t>(hi.z) - lo.z + 1;
    if (nx_ <= 0 || ny_ <= 0 || nz <= 0) {
      nx_ = ny_ = 0;
      return;
    }
    const std::int64_t total = nx_ * ny_ * nz;
    if (total > (std::int64_t{1} << 31)) {
      throw Error(ErrorCode::OutOfRange, "ground truth: the arena holds more than 2^31 voxels at this resolution (use a coarser one)");
    }
    words_ = std::make_unique<std::atomic<std::uint64_t>[]>(static_cast<std::size_t>((total + 63) / 64));
    word_count_ = static_cast<std::size_t>((total + 63) / 64);
    for (std::size_t i = 0; i < word_count_; ++i) words_[i].store(0, std::memory_order_relaxed);
  }

  bool contains(const VoxelKey& k) const {
    return word_count_ > 0 && k.x >= lo_.x && k.y >= lo_.y && k.z >= lo_.z && k.x <= hi_.x && k.y <= hi_.y &&
           k.z <= hi_.z;
  }
  void set(const VoxelKey& k) {
    const std::int64_t i = index(k);
    std::atomic<std::uint64_t>& w = words_[static_cast<std::size_t>(i >> 6)];
    const std::uint64_t bit = std::uint64_t{1} << (i & 63);
    // Reading first keeps already-set cache lines shared between threads.
    if (!(w.load(std::memory_order_relaxed) & bit)) w.fetch_or(bit, std::memory_order_relaxed);
  }
  bool test(const VoxelKey& k) const {
    if (!contains(k)) return false;
    const std::int64_t i = index(k);
    return (words_[static_cast<std::size_t>(i >> 6)].load(std::memory_order_relaxed) >> (i & 63)) & 1u;
  }
  template <class Fn>
  void for_each_set(Fn&& fn) const {
    for (std::size_t w = 0; w < word_count_; ++w) {
      std::uint64_t bits = words_[w].load(std::memory_order_relaxed);
      while (bits) {
        const int b = __builtin_ctzll(bits);
        bits &= bits - 1;
        const std::int64_t i = static_cast<std::int64_t>(w) * 64 + b;
        fn(VoxelKey{static_cast<std::int32_t>(lo_.x + i % nx_), static_cast<std::int32_t>(lo_.y + (i / nx_) % ny_),
                    static_cast<std::int32_t>(lo_.z + i / (nx_ * ny_))});
      }
    }
  }

 private:
  std::int64_t index(const VoxelKey& k) const {
    return (static_cast<std::int64_t>(k.z) - lo_.z) * nx_ * ny_ + (static_cast<std::int64_t>(k.y) - lo_.y) * nx_ +
           (static_cast<std::int64_t>(k.x) - lo_.x);
  }
  VoxelKey lo_, hi_;
  std::int64_t nx_ = 0, ny_ = 0;
  std::unique_ptr<std::atomic<std::uint64_t>[]> words_;
  std::size_t word_count_ = 0;
};

// Marks every voxel the segment a -> b crosses before the voxel of b
// (Amanatides & Woo's 3-D DDA), when inside the free grid.
void walk_free(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double res, DenseVoxelBits& free) {
  VoxelKey cur = voxel_key_of(a, res);
  const VoxelKey end = voxel_key_of(b, res);
  const Eigen::Vector3d d = b - a;
  std::int32_t step[3];
  double t_max[3], t_delta[3];
  const std::int32_t c[3] = {cur.x, cur.y, cur.z};
  for (int i = 0; i < 3; ++i) {
    if (d[i] > 0) {
      step[i] = 1;
      t_max[i] = ((c[i] + 1) * res - a[i]) / d[i];
      t_delta[i] = res / d[i];
    } else if (d[i] < 0) {
      step[i] = -1;
      t_max[i] = (c[i] * res - a[i]) / d[i];
      t_delta[i] = -res / d[i];
    } else {
      step[i] = 0;
      t_max[i] = t_delta[i] = std::numeric_limits<double>::infinity();
    }
  }
  // The walk never needs more steps than the keys' Manhattan distance; the
  // bound also stops it should rounding step past `end`.
  std::int64_t budget = std::abs(static_cast<std::int64_t>(end.x) - cur.x) +
                        std::abs(static_cast<std::int64_t>(end.y) - cur.y) +
                        std::abs(static_cast<std::int64_t>(end.z) - cur.z);
  std::int32_t* k[3] = {&cur.x, &cur.y, &cur.z};
  while (!(cur == end) && budget-- >= 0) {
    if (free.contains(cur)) free.set(cur);
    const int axis = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
    if (t_max[axis] > 1.0) break;
    *k[axis] += step[axis];
    t_max[axis] += t_delta[axis];
  }
}

VoxelKey min_key(const Eigen::Vector3d& p, double res) { return voxel_key_of(p, res); }
VoxelKey max_key(const Eigen::Vector3d& p, double res) {
  // The last voxel that overlaps [min, max): ceil(max / res) - 1.
  return {static_cast<std::int32_t>(std::ceil(p.x() / res)) - 1, static_cast<std::int32_t>(std::ceil(p.y() / res)) - 1,
          static_cast<std::int32_t>(std::ceil(p.z() / res)) - 1};
}

void check_options(const GroundTruthOptions& options, const Arena& arena) {
  if (!(options.resolution > 0) || !std::isfinite(options.resolution)) {
    throw Error(ErrorCode::InvalidArgument, "ground truth: resolution must be positive");
  }
  if (options.frame_stride == 0 || options.ray_stride == 0) {
    throw Error(ErrorCode::InvalidArgument, "ground truth: frame_stride and ray_stride must be at least 1");
  }
  const Eigen::Vector3d extent = (arena.bounds_max - arena.bounds_min) / options.resolution;
  if (extent.maxCoeff() > 1e6) {
    throw Error(ErrorCode::OutOfRange, "ground truth: resolution too fine for the arena's bounds");
  }
}

GroundTruthGrid surface_grid(const Arena& arena, const std::vector<ClassedMesh>& meshes,
                             const GroundTruthOptions& options) {
  GroundTruthGrid grid;
  grid.resolution = options.resolution;
  grid.bounds_min = min_key(arena.bounds_min, options.resolution);
  grid.bounds_max = max_key(arena.bounds_max, options.resolution);
  for (const ClassedMesh& m : meshes) add_surface_voxels(m, options.resolution, grid.occupied);
  return grid;
}

}  // namespace

std::array<std::size_t, kClassCount> GroundTruthGrid::occupied_per_class(bool observed_only) const {
  std::array<std::size_t, kClassCount> counts{};
  for (const auto& [key, voxel] : occupied) {
    if (!observed_only || voxel.observed) ++counts[static_cast<std::size_t>(voxel.label)];
  }
  return counts;
}

void add_surface_voxels(const ClassedMesh& mesh, double resolution, OccupiedVoxelMap& out) {
  // Slivers below a millionth of a voxel face are rounding, not contact.
  SurfaceSplitter splitter{resolution, mesh.label, out, 1e-6 * resolution * resolution};
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    Polygon p;
    p.n = 3;
    for (std::size_t k = 0; k < 3; ++k) p.v[k] = mesh.vertices[mesh.indices[t + k]].cast<double>();
    splitter.split(p, 0, {0, 0, 0});
  }
  update_labels(out);
}

GroundTruthGrid voxelize_arena(const Arena& arena, const GroundTruthOptions& options) {
  if (!options.compute_free) {
    check_options(options, arena);
    return surface_grid(arena, arena_meshes(arena), options);
  }
  SimulationOptions sim_options;
  sim_options.noise = false;
  const Simulator simulator(arena, sim_options);
  return voxelize_arena(simulator, options);
}

GroundTruthGrid voxelize_arena(const Simulator& simulator, const GroundTruthOptions& options) {
  const Arena& arena = simulator.arena();
  check_options(options, arena);
  const double res = options.resolution;
  GroundTruthGrid grid = surface_grid(arena, arena_meshes(arena), options);
  if (!options.compute_free) return grid;

  DenseVoxelBits free(grid.bounds_min, grid.bounds_max);
  const SensorRays& rays = simulator.rays();
  const std::size_t n = rays.directions.size();
  const auto cols = static_cast<std::size_t>(rays.cols);
  const std::size_t stride = options.ray_stride;
  std::vector<float> t(n);
  std::vector<std::uint8_t> labels(n);
  // Voxels where a ray ended, one flag per ray (set in parallel, read serially).
  std::vector<VoxelKey> ends(n), beyonds(n);
  std::vector<std::uint8_t> ended(n);
  for (std::size_t f = 0; f < simulator.frame_count(); f += options.frame_stride) {
    simulator.cast_frame(f, t, labels);
    const Pose& pose = simulator.poses()[f];
    const Eigen::Vector3d o = pose.translation();
    const Eigen::Matrix3d& r = pose.rotation();
    std::fill(ended.begin(), ended.end(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, static_cast<std::size_t>(rays.rows)),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t row = range.begin(); row != range.end(); ++row) {
                          if (row % stride != 0) continue;
                          for (std::size_t col = 0; col < cols; col += stride) {
                            const std::size_t i = row * cols + col;
                            if (!std::isfinite(t[i])) continue;
                            const Eigen::Vector3d d = r * rays.directions[i].cast<double>();
                            // Stop 0.1 mm short of the surface so a surface on a
                            // voxel face ends the walk on its near side.
                            const double back = 1e-4 / d.norm();
                            const Eigen::Vector3d end = o + d * std::max(0.0, t[i] - back);
                            walk_free(o, end, res, free);
                            ends[i] = voxel_key_of(end, res);
                            // The voxel just past the end too: a surface on a voxel
                            // face occupies both sides.
                            beyonds[i] = voxel_key_of(o + d * (t[i] + back), res);
                            ended[i] = 1;
                          }
                        }
                      });
    for (std::size_t i = 0; i < n; ++i) {
      if (!ended[i]) continue;
      for (const VoxelKey& k : {ends[i], beyonds[i]}) {
        const auto it = grid.occupied.find(k);
        if (it != grid.occupied.end()) it->second.observed = true;
      }
    }
  }
  free.for_each_set([&grid](const VoxelKey& k) {
    if (!grid.occupied.count(k)) grid.free.insert(k);
  });
  return grid;
}

}  // namespace sarmap::sim
