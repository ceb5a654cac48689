#include "engine/semantic/surface_normals.hpp"

#include <array>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/core/error.hpp"
#include "engine/core/flat_key_map.hpp"
#include "engine/semantic/grid_keys.hpp"

namespace sarmap {

namespace {

// The metric map's coordinate limit (metres from the origin): cells of
// 1 cm or more relative to a point within it fit grid_keys::cell_key.
constexpr double kWorldLimit = 10'000.0;

// Sums of coordinates relative to a reference point near the cloud, so the
// covariance does not lose precision far from the world origin.
struct CellSums {
  double n = 0;
  std::array<double, 3> s{};
  std::array<double, 6> ss{};  // xx, xy, xz, yy, yz, zz
  void add(double x, double y, double z) {
    n += 1;
    s[0] += x, s[1] += y, s[2] += z;
    ss[0] += x * x, ss[1] += x * y, ss[2] += x * z, ss[3] += y * y, ss[4] += y * z, ss[5] += z * z;
  }
  void add(const CellSums& o) {
    n += o.n;
    for (int a = 0; a < 3; ++a) s[a] += o.s[a];
    for (int a = 0; a < 6; ++a) ss[a] += o.ss[a];
  }
};


struct PlaneFit {
  std::array<float, 3> normal{0.f, 0.f, 1.f};
  float curvature = 1.f;  // smallest eigenvalue / sum of eigenvalues: 0 on a plane, 1/3 isotropic
  bool valid = false;
};

PlaneFit fit_plane(const CellSums& sums, std::size_t min_points) {
  PlaneFit fit;
  if (sums.n < static_cast<double>(min_points)) return fit;
  const double m = 1.0 / sums.n;
  const double mx = sums.s[0] * m, my = sums.s[1] * m, mz = sums.s[2] * m;
  Eigen::Matrix3d cov;
  cov(0, 0) = sums.ss[0] * m - mx * mx;
  cov(0, 1) = cov(1, 0) = sums.ss[1] * m - mx * my;
  cov(0, 2) = cov(2, 0) = sums.ss[2] * m - mx * mz;
  cov(1, 1) = sums.ss[3] * m - my * my;
  cov(1, 2) = cov(2, 1) = sums.ss[4] * m - my * mz;
  cov(2, 2) = sums.ss[5] * m - mz * mz;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(cov);
  if (solver.info() != Eigen::Success) return fit;
  Eigen::Vector3d normal = solver.eigenvectors().col(0);  // smallest eigenvalue first
  if (normal.z() < 0) normal = -normal;
  if (!normal.allFinite() || normal.norm() < 0.5) return fit;
  normal.normalize();
  const Eigen::Vector3d lambda = solver.eigenvalues().cwiseMax(0.0);
  const double total = lambda.sum();
  fit.normal = {static_cast<float>(normal.x()), static_cast<float>(normal.y()), static_cast<float>(normal.z())};
  fit.curvature = total > 0 ? static_cast<float>(lambda[0] / total) : 0.f;
  fit.valid = true;
  return fit;
}

}  // namespace

SurfaceNormals estimate_surface_normals(const PointBuffer& points, const SurfaceNormalSettings& settings) {
  if (!(settings.cell >= 0.01) || !std::isfinite(settings.cell)) {
    throw Error(ErrorCode::InvalidArgument, "surface normals: cell size must be at least 0.01 m");
  }
  const std::size_t n = points.size();
  SurfaceNormals out;
  out.nx.assign(n, 0.f), out.ny.assign(n, 0.f), out.nz.assign(n, 1.f), out.valid.assign(n, 0);
  out.curvature.assign(n, 1.f);
  if (n == 0) return out;
  const double inv = 1.0 / settings.cell;
  // Points farther than the metric map's limit are left without a normal
  // (the map rejects them too); the rest are binned relative to the first of
  // them, which keeps cell indices and sums small.
  const auto in_limits = [](double x, double y, double z) {
    return std::abs(x) <= kWorldLimit && std::abs(y) <= kWorldLimit && std::abs(z) <= kWorldLimit;
  };
  std::size_t first = 0;
  while (first < n && !in_limits(points.x()[first], points.y()[first], points.z()[first])) ++first;
  if (first == n) return out;
  const double rx = points.x()[first], ry = points.y()[first], rz = points.z()[first];

  constexpr std::uint32_t kNoCell = ~std::uint32_t{0};
  std::vector<std::uint32_t> cell_of(n, kNoCell);
  std::vector<std::array<std::int64_t, 3>> cell_coords;
  FlatKeyMap<CellSums> cells(n / 16);
  std::vector<CellSums>& sums = cells.values();
  // Neighbouring points (a depth image's row, a ring) mostly share a cell:
  // the last cell's index is taken without a hash lookup.
  std::uint64_t last_key = 0;
  std::uint32_t last_cell = kNoCell;
  for (std::size_t p = 0; p < n; ++p) {
    const double x = points.x()[p], y = points.y()[p], z = points.z()[p];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      throw Error(ErrorCode::InvalidArgument, "surface normals: point " + std::to_string(p) + " is not finite");
    }
    if (!in_limits(x, y, z)) continue;
    const std::array<std::int64_t, 3> c{static_cast<std::int64_t>(std::floor((x - rx) * inv)),
                                        static_cast<std::int64_t>(std::floor((y - ry) * inv)),
                                        static_cast<std::int64_t>(std::floor((z - rz) * inv))};
    const std::uint64_t key = grid_keys::cell_key(c[0], c[1], c[2]);
    if (last_cell == kNoCell || key != last_key) {
      last_key = key;
      const auto [cell, is_new] = cells.try_emplace(key);
      last_cell = cell;
      if (is_new) cell_coords.push_back(c);
    }
    sums[last_cell].add(x - rx, y - ry, z - rz);
    cell_of[p] = last_cell;
  }

  // One plane fit per cell over its 27-cell neighbourhood; where that
  // neighbourhood spans an edge (a wall's foot, a box's rim) the fit mixes
  // two planes, so the cell's own points are tried alone and the flatter fit
  // is kept.
  std::vector<PlaneFit> cell_fit(sums.size());
  tbb::parallel_for(std::size_t{0}, sums.size(), [&](std::size_t c) {
    CellSums pooled;
    const auto& cc = cell_coords[c];
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        for (int dk = -1; dk <= 1; ++dk) {
          if (const CellSums* other = cells.find(grid_keys::cell_key(cc[0] + di, cc[1] + dj, cc[2] + dk))) {
            pooled.add(*other);
          }
        }
    PlaneFit fit = fit_plane(pooled, settings.min_points);
    if (!fit.valid || fit.curvature > settings.max_curvature) {
      const PlaneFit own = fit_plane(sums[c], settings.min_points);
      if (own.valid && (!fit.valid || own.curvature < fit.curvature)) fit = own;
    }
    cell_fit[c] = fit;
  });

  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t p = r.begin(); p != r.end(); ++p) {
      const std::uint32_t c = cell_of[p];
      if (c == kNoCell || !cell_fit[c].valid) continue;
      const PlaneFit& f = cell_fit[c];
      out.nx[p] = f.normal[0], out.ny[p] = f.normal[1], out.nz[p] = f.normal[2];
      out.curvature[p] = f.curvature;
      out.valid[p] = 1;
    }
  });
  return out;
}

}  // namespace sarmap
