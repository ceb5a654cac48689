// RANSAC for one plane in a set of points: three-point samples, the second
// and third drawn near the first (one surface among many is then found in
// few draws), inliers counted over every point. Samples come from a
// counter-based hash of (seed, iteration) and are scored in fixed batches, so
// the answer is the same for a seed whatever the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/segments/plane.hpp"

namespace sarmap::segments {

// Points as structure of arrays, so the inlier count is one vectorised loop.
struct PlanePoints {
  std::span<const float> x, y, z;
  std::size_t size() const { return x.size(); }
};

struct RansacOptions {
  double threshold = 0.02;           // inlier distance, metres
  double confidence = 0.99;          // chance of having drawn one all-inlier sample
  std::size_t max_iterations = 1000;
  std::size_t min_inliers = 3;       // a best plane with fewer is no plane
  std::uint64_t seed = 1;
  double neighbourhood = 0.5;        // the 2nd and 3rd sample share the 1st one's cell of this size, metres
};

struct RansacResult {
  bool found = false;
  Plane plane;                 // from the best sample (refine it with fit_plane on the inliers)
  std::size_t inliers = 0;
  std::size_t iterations = 0;  // samples drawn
};

// The iteration count that gives `confidence` of one all-inlier three-point
// sample when a fraction `inlier_ratio` of the points are inliers.
std::size_t ransac_iterations(double inlier_ratio, double confidence, std::size_t max_iterations);

// Throws sarmap::Error (InvalidArgument) for a threshold <= 0 or NaN and for
// non-finite points.
RansacResult find_plane(const PlanePoints& points, const RansacOptions& options);

// Points within `threshold` of the plane, as indices in increasing order.
std::vector<std::uint32_t> plane_inliers(const PlanePoints& points, const Plane& plane, double threshold);

}  // namespace sarmap::segments
