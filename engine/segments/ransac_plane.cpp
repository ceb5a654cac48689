#include "engine/segments/ransac_plane.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/core/error.hpp"
#include "engine/core/flat_key_index.hpp"

namespace sarmap::segments {
namespace {

// Hypotheses scored per round: fixed, so where the adaptive count stops never
// depends on how many threads scored the round.
constexpr std::size_t kBatch = 32;

std::uint64_t draw(std::uint64_t seed, std::uint64_t iteration, std::uint64_t k) {
  return mix_key(mix_key(seed ^ 0x9E3779B97F4A7C15ull) ^ (iteration * 4 + k));
}

std::size_t count_inliers(const PlanePoints& p, const Plane& plane, double threshold) {
  const auto a = static_cast<float>(plane.normal.x());
  const auto b = static_cast<float>(plane.normal.y());
  const auto c = static_cast<float>(plane.normal.z());
  const auto d = static_cast<float>(plane.offset);
  const auto t = static_cast<float>(threshold);
  const float* x = p.x.data();
  const float* y = p.y.data();
  const float* z = p.z.data();
  std::size_t count = 0;
  for (std::size_t i = 0; i < p.size(); ++i) count += std::fabs(a * x[i] + b * y[i] + c * z[i] + d) <= t;
  return count;
}

// Points grouped by the cell of the neighbourhood grid: order[begin..end) of a cell.
struct CellBuckets {
  std::vector<std::uint32_t> order;
  std::vector<std::uint32_t> begin_of_point, end_of_point;  // the range of each point's cell

  CellBuckets(const PlanePoints& p, double cell) {
    const double inv = 1.0 / cell;
    const std::size_t n = p.size();
    FlatKeyIndex cells(n / 4 + 16);
    std::vector<std::uint32_t> cell_of(n);
    for (std::size_t i = 0; i < n; ++i) {
      // 21 bits per axis: a 0.5 m cell reaches 500 km, beyond any map.
      const auto ix = static_cast<std::int64_t>(std::floor(p.x[i] * inv)) & 0x1fffff;
      const auto iy = static_cast<std::int64_t>(std::floor(p.y[i] * inv)) & 0x1fffff;
      const auto iz = static_cast<std::int64_t>(std::floor(p.z[i] * inv)) & 0x1fffff;
      cell_of[i] = cells.find_or_insert(static_cast<std::uint64_t>(ix | (iy << 21) | (iz << 42)));
    }
    std::vector<std::uint32_t> start(cells.size() + 1, 0);
    for (std::uint32_t c : cell_of) ++start[c + 1];
    for (std::size_t c = 0; c < cells.size(); ++c) start[c + 1] += start[c];
    order.resize(n);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t i = 0; i < n; ++i) order[fill[cell_of[i]]++] = i;
    begin_of_point.resize(n);
    end_of_point.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      begin_of_point[i] = start[cell_of[i]];
      end_of_point[i] = start[cell_of[i] + 1];
    }
  }
};

Eigen::Vector3d point(const PlanePoints& p, std::size_t i) { return {p.x[i], p.y[i], p.z[i]}; }

// The plane through the iteration's sample, or none for a degenerate sample.
bool sample_plane(const PlanePoints& p, const CellBuckets& buckets, std::uint64_t seed, std::uint64_t iteration,
                  Plane& plane) {
  const std::size_t n = p.size();
  const auto first = static_cast<std::uint32_t>(draw(seed, iteration, 0) % n);
  std::array<std::uint32_t, 3> pick{first, 0, 0};
  const std::uint32_t begin = buckets.begin_of_point[first];
  const std::uint32_t size = buckets.end_of_point[first] - begin;
  for (std::uint64_t k = 1; k < 3; ++k) {
    pick[k] = size >= 3 ? buckets.order[begin + draw(seed, iteration, k) % size]
                        : static_cast<std::uint32_t>(draw(seed, iteration, k) % n);
  }
  const Eigen::Vector3d a = point(p, pick[0]);
  const Eigen::Vector3d normal = (point(p, pick[1]) - a).cross(point(p, pick[2]) - a);
  const double length = normal.norm();
  // Collinear or repeated points: no plane (1e-8 m^2 is a 0.1 mm triangle).
  if (!(length > 1e-8)) return false;
  plane.normal = normal / length;
  plane.offset = -plane.normal.dot(a);
  return true;
}

}  // namespace

std::size_t ransac_iterations(double inlier_ratio, double confidence, std::size_t max_iterations) {
  const double w3 = inlier_ratio * inlier_ratio * inlier_ratio;
  if (w3 >= 1.0) return 1;
  if (!(w3 > 0.0)) return max_iterations;
  const double n = std::ceil(std::log(1.0 - confidence) / std::log(1.0 - w3));
  if (!(n < static_cast<double>(max_iterations))) return max_iterations;
  return std::max<std::size_t>(1, static_cast<std::size_t>(n));
}

RansacResult find_plane(const PlanePoints& points, const RansacOptions& o) {
  if (!(o.threshold > 0) || !std::isfinite(o.threshold)) {
    throw Error(ErrorCode::InvalidArgument, "RANSAC: the inlier threshold must be > 0, got " +
                                                std::to_string(o.threshold));
  }
  if (!(o.confidence > 0 && o.confidence < 1)) {
    throw Error(ErrorCode::InvalidArgument, "RANSAC: confidence must be in (0, 1)");
  }
  if (!(o.neighbourhood > 0) || !std::isfinite(o.neighbourhood)) {
    throw Error(ErrorCode::InvalidArgument, "RANSAC: the sampling neighbourhood must be > 0");
  }
  const std::size_t n = points.size();
  if (points.y.size() != n || points.z.size() != n) {
    throw Error(ErrorCode::InvalidArgument, "RANSAC: x, y and z hold different numbers of points");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(points.x[i]) || !std::isfinite(points.y[i]) || !std::isfinite(points.z[i])) {
      throw Error(ErrorCode::InvalidArgument, "RANSAC: point " + std::to_string(i) + " is not finite");
    }
  }
  RansacResult result;
  if (n < 3 || n < o.min_inliers) return result;
  const CellBuckets buckets(points, o.neighbourhood);
  std::size_t needed = o.max_iterations;
  std::size_t done = 0;
  std::array<Plane, kBatch> planes;
  std::array<std::size_t, kBatch> counts;
  while (done < needed) {
    const std::size_t batch = std::min(kBatch, needed - done);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, batch, 1), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t k = r.begin(); k < r.end(); ++k) {
        counts[k] = sample_plane(points, buckets, o.seed, done + k, planes[k])
                        ? count_inliers(points, planes[k], o.threshold)
                        : 0;
      }
    });
    // In iteration order, strictly better only: ties go to the earlier sample.
    for (std::size_t k = 0; k < batch; ++k) {
      if (counts[k] > result.inliers) {
        result.inliers = counts[k];
        result.plane = planes[k];
      }
    }
    done += batch;
    needed = std::min(o.max_iterations,
                      ransac_iterations(static_cast<double>(result.inliers) / static_cast<double>(n), o.confidence,
                                        o.max_iterations));
  }
  result.iterations = done;
  result.found = result.inliers >= std::max<std::size_t>(3, o.min_inliers);
  return result;
}

std::vector<std::uint32_t> plane_inliers(const PlanePoints& p, const Plane& plane, double threshold) {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (std::abs(plane.distance(point(p, i))) <= threshold) out.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

}  // namespace sarmap::segments
