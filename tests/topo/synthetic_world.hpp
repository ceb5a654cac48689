// A small world built by hand for the topo tests, as the metric map and the
// labelled points a run would produce, without the simulator: a 4 x 3 m
// floor, a wall across it at x = 2 with a 0.8 m doorway (y 1.1 to 1.9), and a
// 0.3 m platform with no ramp (x 3.0 to 3.8, y 0.4 to 1.2). Space up to 1 m
// above the floor is seen free; nothing beyond the floor is seen.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/core/point_buffer.hpp"
#include "engine/metric/metric_map.hpp"
#include "engine/segments/segment_map.hpp"

namespace sarmap::topo::testing {

struct Solid {
  Eigen::Vector3d min, max;
  ClassId label;
  bool contains(const Eigen::Vector3d& p) const { return (p.array() >= min.array()).all() && (p.array() <= max.array()).all(); }
};

inline std::vector<Solid> world_solids() {
  return {{{1.95, 0, 0}, {2.05, 1.1, 1.0}, ClassId::Wall},
          {{1.95, 1.9, 0}, {2.05, 3.0, 1.0}, ClassId::Wall},
          {{3.0, 0.4, 0}, {3.8, 1.2, 0.3}, ClassId::FlatRamp}};
}

inline void set_voxel(metric::MetricMap& map, const Eigen::Vector3d& p, bool occupied, ClassId label) {
  metric::SemanticVoxel v{occupied ? map.occupancy().max() : map.occupancy().min(), {}};
  if (occupied) v.evidence[static_cast<std::size_t>(label)] = 120;
  map.blocks().set_voxel(*map.key_at(p), v);
}

inline metric::MetricMap world_map() {
  metric::MetricMap map(metric::settings_at_resolution(0.05));
  const auto solids = world_solids();
  const double r = 0.05;
  for (int i = 0; i < 80; ++i) {
    for (int j = 0; j < 60; ++j) {
      const double x = (i + 0.5) * r, y = (j + 0.5) * r;
      bool under_solid = false;
      for (const Solid& s : solids) under_solid |= s.contains({x, y, 0.01});
      if (!under_solid) set_voxel(map, {x, y, -0.025}, true, ClassId::Terrain);
      for (int k = 0; k < 20; ++k) {
        const Eigen::Vector3d c(x, y, (k + 0.5) * r);
        const Solid* in = nullptr;
        for (const Solid& s : solids) {
          if (s.contains(c)) in = &s;
        }
        if (in == nullptr) {
          set_voxel(map, c, false, ClassId::Unknown);
          continue;
        }
        // A solid's surface voxels are occupied; its inside was never seen.
        const bool surface = !in->contains(c + Eigen::Vector3d(r, 0, 0)) || !in->contains(c - Eigen::Vector3d(r, 0, 0)) ||
                             !in->contains(c + Eigen::Vector3d(0, r, 0)) || !in->contains(c - Eigen::Vector3d(0, r, 0)) ||
                             !in->contains(c + Eigen::Vector3d(0, 0, r));
        if (surface) set_voxel(map, c, true, in->label);
      }
    }
  }
  return map;
}

// Labelled surface points every 2 cm: the floor, the walls' faces, the platform's top and sides.
inline PointBuffer world_points() {
  PointBuffer out;
  out.enable_labels();
  const auto solids = world_solids();
  auto add = [&out](const Eigen::Vector3d& p, ClassId label) {
    out.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    out.labels()[out.size() - 1] = static_cast<std::uint8_t>(label);
  };
  const double step = 0.02;
  for (double x = 0; x <= 4.0 + 1e-9; x += step) {
    for (double y = 0; y <= 3.0 + 1e-9; y += step) {
      bool under = false;
      for (const Solid& s : solids) under |= s.contains({x, y, 0.001}) && x > s.min.x() && x < s.max.x() && y > s.min.y() && y < s.max.y();
      if (!under) add({x, y, 0}, ClassId::Terrain);
    }
  }
  for (const Solid& s : solids) {
    // Vertical faces at x = min / max and y = min / max, then the top.
    for (double z = step; z <= s.max.z() + 1e-9; z += step) {
      for (double y = s.min.y(); y <= s.max.y() + 1e-9; y += step) {
        add({s.min.x(), y, z}, s.label);
        add({s.max.x(), y, z}, s.label);
      }
      for (double x = s.min.x(); x <= s.max.x() + 1e-9; x += step) {
        add({x, s.min.y(), z}, s.label);
        add({x, s.max.y(), z}, s.label);
      }
    }
    for (double x = s.min.x(); x <= s.max.x() + 1e-9; x += step) {
      for (double y = s.min.y(); y <= s.max.y() + 1e-9; y += step) add({x, y, s.max.z()}, s.label);
    }
  }
  return out;
}

// The points as two scans, each seen from its side of the wall.
inline segments::SegmentMap world_segments() {
  const PointBuffer all = world_points();
  segments::SegmentSettings settings;
  settings.max_range = 0;
  segments::SegmentMap map(settings);
  for (const bool left : {true, false}) {
    std::vector<std::uint32_t> keep;
    for (std::uint32_t i = 0; i < all.size(); ++i) {
      if ((all.x()[i] < 2.0) == left) keep.push_back(i);
    }
    map.integrate(all.select(keep), left ? Eigen::Vector3d(1, 1.5, 0.6) : Eigen::Vector3d(3, 2, 0.6));
  }
  return map;
}

}  // namespace sarmap::topo::testing
