// Region growing in a plane: the inliers of one plane split into connected
// surfaces, so two walls on one line with a doorway between, or two platforms
// at one height, become two segments. Points fall into square cells of the
// given size; cells touching by side or corner are connected.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace sarmap::segments {

// Connected groups of the points (in-plane coordinates), as indices into
// `points` in increasing order; groups ordered by size (largest first), then
// by their smallest index. Throws sarmap::Error (InvalidArgument) for a cell
// size <= 0.
std::vector<std::vector<std::uint32_t>> plane_regions(std::span<const Eigen::Vector2d> points, double cell);

}  // namespace sarmap::segments
