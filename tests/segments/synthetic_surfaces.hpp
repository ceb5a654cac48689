// Labelled points on exact rectangles, for the segment tests: a floor, walls
// with a doorway, a platform, each sampled on a grid with optional noise.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/core/point_buffer.hpp"

namespace sarmap::segments::testing {

// A rectangle corner + two edge vectors, sampled every `step` metres.
struct Patch {
  Eigen::Vector3d corner, edge_a, edge_b;
  ClassId label;
};

inline void add_patch(PointBuffer& out, const Patch& patch, double step, double noise = 0, std::uint32_t seed = 1) {
  if (!out.has_labels()) out.enable_labels();
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise > 0 ? noise : 1.0);
  const Eigen::Vector3d normal = patch.edge_a.cross(patch.edge_b).normalized();
  const int na = static_cast<int>(patch.edge_a.norm() / step);
  const int nb = static_cast<int>(patch.edge_b.norm() / step);
  for (int i = 0; i <= na; ++i) {
    for (int k = 0; k <= nb; ++k) {
      Eigen::Vector3d p = patch.corner + patch.edge_a * (i / static_cast<double>(na)) +
                          patch.edge_b * (k / static_cast<double>(nb));
      if (noise > 0) p += normal * gauss(rng);
      out.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
      out.labels()[out.size() - 1] = static_cast<std::uint8_t>(patch.label);
    }
  }
}

// Floor 0..4 x 0..3; a wall along y = 3 from x = 0 to 1.5 and from 2.3 to 4
// (a 0.8 m doorway), its face towards -y; a platform top at z = 0.3 over
// 2.5..3.5 x 0.5..1.5, and a second platform top at the same height over
// 0.5..1.3 x 0.5..1.5.
inline std::vector<Patch> small_arena() {
  using V = Eigen::Vector3d;
  return {
      {V(0, 0, 0), V(4, 0, 0), V(0, 3, 0), ClassId::Terrain},
      {V(0, 2.95, 0), V(1.5, 0, 0), V(0, 0, 1.2), ClassId::Wall},
      {V(2.3, 2.95, 0), V(1.7, 0, 0), V(0, 0, 1.2), ClassId::Wall},
      {V(2.5, 0.5, 0.3), V(1, 0, 0), V(0, 1, 0), ClassId::FlatRamp},
      {V(0.5, 0.5, 0.3), V(0.8, 0, 0), V(0, 1, 0), ClassId::FlatRamp},
  };
}

// The patches seen as a sensor moving along x would see them: in `scans`
// overlapping stripes over x in [0, 4], sampled every `step` metres with the
// given noise (seeds from `seed` on, one per patch).
inline std::vector<PointBuffer> stripes(const std::vector<Patch>& patches, int scans, double step = 0.02,
                                        double noise = 0, std::uint32_t seed = 1) {
  PointBuffer all;
  for (const Patch& p : patches) add_patch(all, p, step, noise, seed++);
  std::vector<PointBuffer> out(scans);
  for (int s = 0; s < scans; ++s) {
    const double lo = 4.0 * s / scans - 0.3, hi = 4.0 * (s + 1) / scans + 0.3;
    std::vector<std::uint32_t> keep;
    for (std::uint32_t i = 0; i < all.size(); ++i) {
      if (all.x()[i] >= lo && all.x()[i] <= hi) keep.push_back(i);
    }
    out[s] = all.select(keep);
  }
  return out;
}

}  // namespace sarmap::segments::testing
