// A closed room with a box and a ramp-like slab, seen by a pinhole depth
// camera moving along a circle: exact ray/box intersections give labelled
// world-frame points, so metric tests (and the benchmark, until a simulated
// sequence is at hand) have realistic scans without any input files.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/core/classes.hpp"
#include "engine/core/point_buffer.hpp"

namespace sarmap::testing {

struct RoomScan {
  PointBuffer points;
  Eigen::Vector3d origin;
};

struct AlignedBox {
  Eigen::Vector3d lo, hi;
  ClassId cls;
};

// Room 6 x 4 x 2.5 m (x in [0,6], y in [0,4], z in [0,2.5]), floor terrain, walls wall.
class SyntheticRoom {
 public:
  SyntheticRoom() {
    obstacles_.push_back({{2.0, 1.2, 0.0}, {2.8, 2.0, 0.6}, ClassId::Other});
    obstacles_.push_back({{3.8, 2.4, 0.0}, {5.2, 3.3, 0.3}, ClassId::FlatRamp});
  }

  // Frame i of n: the camera circles the room centre at 1.2 m height looking outwards
  // and slightly down, so walls, floor and obstacles are all seen.
  RoomScan frame(int i, int n, int width, int height) const {
    const double angle = 2.0 * M_PI * i / n;
    RoomScan scan;
    scan.origin = Eigen::Vector3d(3.0 + 0.8 * std::cos(angle), 2.0 + 0.6 * std::sin(angle), 1.2);
    const Eigen::Vector3d forward =
        Eigen::Vector3d(std::cos(angle + 0.4), std::sin(angle + 0.4), -0.35).normalized();
    const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d down = forward.cross(right);
    const double f = width / (2.0 * std::tan(0.5 * 1.05));  // 60 degree horizontal field of view
    scan.points.enable_labels();
    scan.points.reserve(static_cast<std::size_t>(width) * height);
    for (int v = 0; v < height; ++v) {
      for (int u = 0; u < width; ++u) {
        const Eigen::Vector3d d =
            (forward + right * ((u + 0.5 - width / 2.0) / f) + down * ((v + 0.5 - height / 2.0) / f)).normalized();
        ClassId cls;
        const double t = cast(scan.origin, d, cls);
        const Eigen::Vector3d p = scan.origin + d * t;
        scan.points.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
        scan.points.labels()[scan.points.size() - 1] = static_cast<std::uint8_t>(cls);
      }
    }
    return scan;
  }

 private:
  // Distance to the first surface along d from o (inside the room).
  double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, ClassId& cls) const {
    const Eigen::Vector3d room_hi(6.0, 4.0, 2.5);
    double best = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      if (d[a] == 0) continue;
      const double t = ((d[a] > 0 ? room_hi[a] : 0.0) - o[a]) / d[a];
      if (t < best) {
        best = t;
        cls = (a == 2 && d[a] < 0) ? ClassId::Terrain : ClassId::Wall;
      }
    }
    for (const AlignedBox& box : obstacles_) {
      double t0 = 0, t1 = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        if (d[a] == 0) {
          if (o[a] < box.lo[a] || o[a] > box.hi[a]) t0 = t1 + 1;
          continue;
        }
        double ta = (box.lo[a] - o[a]) / d[a], tb = (box.hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      if (t0 <= t1 && t0 < best) {
        best = t0;
        cls = box.cls;
      }
    }
    return best;
  }
  std::vector<AlignedBox> obstacles_;
};

}  // namespace sarmap::testing
