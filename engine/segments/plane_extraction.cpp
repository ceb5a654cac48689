#include "engine/segments/plane_extraction.hpp"

#include <numeric>

#include "engine/core/flat_key_index.hpp"
#include "engine/segments/plane_moments.hpp"
#include "engine/segments/plane_regions.hpp"

namespace sarmap::segments {
namespace {

// The points still in the search, copied contiguous so RANSAC streams them.
struct ActivePoints {
  std::vector<std::uint32_t> source;  // index into the input
  std::vector<float> x, y, z;

  PlanePoints view() const { return {x, y, z}; }
  Eigen::Vector3d point(std::size_t i) const { return {x[i], y[i], z[i]}; }

  void keep(const std::vector<bool>& drop) {
    std::size_t out = 0;
    for (std::size_t i = 0; i < source.size(); ++i) {
      if (drop[i]) continue;
      source[out] = source[i];
      x[out] = x[i];
      y[out] = y[i];
      z[out] = z[i];
      ++out;
    }
    source.resize(out);
    x.resize(out);
    y.resize(out);
    z.resize(out);
  }
};

}  // namespace

Extraction extract_surfaces(const PlanePoints& points, const SegmentSettings& s, std::uint64_t seed) {
  validate(s);
  Extraction out;
  ActivePoints active;
  active.source.resize(points.size());
  std::iota(active.source.begin(), active.source.end(), 0u);
  active.x.assign(points.x.begin(), points.x.end());
  active.y.assign(points.y.begin(), points.y.end());
  active.z.assign(points.z.begin(), points.z.end());

  RansacOptions options;
  options.threshold = s.distance_threshold;
  options.confidence = s.confidence;
  options.max_iterations = s.max_iterations;
  options.min_inliers = s.min_points;
  for (std::uint64_t round = 0; active.source.size() >= s.min_points; ++round) {
    options.seed = mix_key(seed + round);
    const RansacResult found = find_plane(active.view(), options);
    if (!found.found) break;
    // Least squares on the sample's inliers, then the inliers of the refit plane.
    std::vector<std::uint32_t> inliers = plane_inliers(active.view(), found.plane, s.distance_threshold);
    PlaneMoments moments;
    for (std::uint32_t i : inliers) moments.add(active.point(i));
    const PlaneFit fit = fit_plane(moments);
    std::vector<std::uint32_t> refit = plane_inliers(active.view(), fit.plane, s.distance_threshold);
    if (refit.size() >= inliers.size()) inliers = std::move(refit);
    if (inliers.empty()) break;
    ++out.planes;

    const PlaneFrame frame(fit.centroid, fit.plane.normal);
    std::vector<Eigen::Vector2d> in_plane(inliers.size());
    for (std::size_t k = 0; k < inliers.size(); ++k) in_plane[k] = frame.project(active.point(inliers[k]));
    for (const std::vector<std::uint32_t>& region : plane_regions(in_plane, s.cluster_radius)) {
      if (region.size() < s.min_points) break;  // regions come largest first
      std::vector<std::uint32_t> surface(region.size());
      for (std::size_t k = 0; k < region.size(); ++k) surface[k] = active.source[inliers[region[k]]];
      out.surfaces.push_back(std::move(surface));
    }
    std::vector<bool> drop(active.source.size(), false);
    for (std::uint32_t i : inliers) drop[i] = true;
    active.keep(drop);
  }
  return out;
}

}  // namespace sarmap::segments
