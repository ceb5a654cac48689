// Planes out of one class's points, the way paper 002 does it: RANSAC finds
// the plane with the most inliers, least squares refits it on them, region
// growing splits its inliers into connected surfaces; the inliers leave and
// the search repeats until too few points remain or no plane is found.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/segments/ransac_plane.hpp"
#include "engine/segments/segment_settings.hpp"

namespace sarmap::segments {

struct Extraction {
  // Connected surfaces of at least settings.min_points points, as indices
  // into the input, in the order found.
  std::vector<std::vector<std::uint32_t>> surfaces;
  std::size_t planes = 0;  // RANSAC planes found (a plane may give several surfaces, or none big enough)
};

// Deterministic for (points, settings, seed) whatever the thread count.
// Throws sarmap::Error (InvalidArgument) for non-finite points or bad settings.
Extraction extract_surfaces(const PlanePoints& points, const SegmentSettings& settings, std::uint64_t seed);

}  // namespace sarmap::segments
