#include "engine/eval/drivable_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "engine/core/error.hpp"
#include "engine/sim/arena_mesh.hpp"

namespace sarmap::eval {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool walkable(ClassId label) {
  return label == ClassId::Terrain || label == ClassId::InclinedRamp || label == ClassId::FlatRamp;
}

double edge(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x();
}

}  // namespace

void validate(const DrivableSettings& s) {
  const auto check = [](bool ok, const char* what) {
    if (!ok) throw Error(ErrorCode::InvalidArgument, std::string("drivable grid: ") + what);
  };
  check(std::isfinite(s.cell) && s.cell > 0, "cell must be positive");
  check(std::isfinite(s.robot_radius) && s.robot_radius >= 0, "robot_radius must be at least 0");
  check(std::isfinite(s.max_step) && s.max_step >= 0, "max_step must be at least 0");
  check(std::isfinite(s.surface_tolerance) && s.surface_tolerance >= 0, "surface_tolerance must be at least 0");
}

DrivableGrid::DrivableGrid(const sim::Arena& arena, const DrivableSettings& settings) : settings_(settings) {
  validate(settings_);
  const double cell = settings_.cell;
  origin_ = arena.bounds_min.head<2>();
  const Eigen::Vector2d extent = (arena.bounds_max - arena.bounds_min).head<2>() / cell;
  if (!(extent.x() > 0 && extent.y() > 0) || extent.x() * extent.y() > 1e8) {
    throw Error(ErrorCode::OutOfRange, "drivable grid: the arena's bounds hold no cells or more than 1e8 at this cell size");
  }
  nx_ = static_cast<std::int32_t>(std::ceil(extent.x() - 1e-9));
  ny_ = static_cast<std::int32_t>(std::ceil(extent.y() - 1e-9));
  const std::size_t n = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  surface_.assign(n, kNaN);
  std::vector<double> top(n, -std::numeric_limits<double>::infinity());

  const auto centre_x = [&](std::int32_t i) { return origin_.x() + (i + 0.5) * cell; };
  const auto centre_y = [&](std::int32_t j) { return origin_.y() + (j + 0.5) * cell; };
  // Cells whose centres lie in [lo, hi] along an axis, clamped to the grid.
  const auto centres_in = [&](double lo, double hi, double o, std::int32_t count) {
    const auto a = static_cast<std::int32_t>(std::max(0.0, std::ceil((lo - o) / cell - 0.5)));
    const auto b = static_cast<std::int32_t>(std::min<double>(count - 1, std::floor((hi - o) / cell - 0.5)));
    return std::pair{a, b};
  };

  for (const sim::ClassedMesh& mesh : sim::arena_meshes(arena)) {
    const bool walk = walkable(mesh.label);
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const Eigen::Vector3d a = mesh.vertices[mesh.indices[t]].cast<double>();
      const Eigen::Vector3d b = mesh.vertices[mesh.indices[t + 1]].cast<double>();
      const Eigen::Vector3d c = mesh.vertices[mesh.indices[t + 2]].cast<double>();
      const Eigen::Vector3d normal = (b - a).cross(c - a);
      if (!(normal.norm() > 0)) continue;
      if (std::abs(normal.z()) <= 1e-9 * normal.norm()) {
        if (walk) continue;  // a platform's or ramp's side: a drop, not an obstacle
        // A vertical obstacle face: every cell its footprint crosses, sampled
        // a hair inside the solid so a face on a cell boundary marks only the
        // cell behind it.
        const Eigen::Vector2d inward = -normal.head<2>().normalized() * 1e-6;
        const double z = std::max({a.z(), b.z(), c.z()});
        const Eigen::Vector2d pts[3] = {a.head<2>(), b.head<2>(), c.head<2>()};
        for (int e = 0; e < 3; ++e) {
          const Eigen::Vector2d p = pts[e] + inward, q = pts[(e + 1) % 3] + inward;
          const int steps = 1 + static_cast<int>(std::ceil(4 * (q - p).norm() / cell));
          for (int k = 0; k <= steps; ++k) {
            const Eigen::Vector2d s = p + (q - p) * (static_cast<double>(k) / steps);
            if (const auto cell_at = cell_of(s.x(), s.y())) top[index(*cell_at)] = std::max(top[index(*cell_at)], z);
          }
        }
        continue;
      }
      if (walk && normal.z() < 0) continue;  // an underside
      const Eigen::Vector2d pa = a.head<2>(), pb = b.head<2>(), pc = c.head<2>();
      const double orient = edge(pa, pb, pc) > 0 ? 1.0 : -1.0;
      const double eps = 1e-9 * (pb - pa).norm() * (pc - pa).norm();
      const auto [i0, i1] = centres_in(std::min({pa.x(), pb.x(), pc.x()}), std::max({pa.x(), pb.x(), pc.x()}),
                                       origin_.x(), nx_);
      const auto [j0, j1] = centres_in(std::min({pa.y(), pb.y(), pc.y()}), std::max({pa.y(), pb.y(), pc.y()}),
                                       origin_.y(), ny_);
      for (std::int32_t j = j0; j <= j1; ++j) {
        for (std::int32_t i = i0; i <= i1; ++i) {
          const Eigen::Vector2d p(centre_x(i), centre_y(j));
          // Edges count as inside, so a quad's diagonal leaves no gap.
          if (orient * edge(pa, pb, p) < -eps || orient * edge(pb, pc, p) < -eps || orient * edge(pc, pa, p) < -eps) {
            continue;
          }
          const double z = a.z() - (normal.x() * (p.x() - a.x()) + normal.y() * (p.y() - a.y())) / normal.z();
          const std::size_t k = index({i, j});
          if (walk) {
            surface_[k] = std::isnan(surface_[k]) ? z : std::max(surface_[k], z);
          } else {
            top[k] = std::max(top[k], z);
          }
        }
      }
    }
  }

  obstacle_.assign(n, 0);
  blocked_.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const bool has_top = std::isfinite(top[k]);
    obstacle_[k] = has_top && (std::isnan(surface_[k]) || top[k] > surface_[k] + settings_.max_step);
    blocked_[k] = obstacle_[k] || std::isnan(surface_[k]);
  }
  // Only obstacle cells on an obstacle's edge can be the nearest one.
  const double reach = settings_.robot_radius / cell + 0.5;
  const auto r = static_cast<std::int32_t>(std::ceil(reach));
  std::vector<GridCell> disk;
  for (std::int32_t dy = -r; dy <= r; ++dy) {
    for (std::int32_t dx = -r; dx <= r; ++dx) {
      if (dx * dx + dy * dy < reach * reach) disk.push_back({dx, dy});
    }
  }
  for (std::int32_t j = 0; j < ny_; ++j) {
    for (std::int32_t i = 0; i < nx_; ++i) {
      if (!obstacle_[index({i, j})]) continue;
      bool edge_cell = false;
      for (const GridCell d : {GridCell{1, 0}, GridCell{-1, 0}, GridCell{0, 1}, GridCell{0, -1}}) {
        const GridCell nb{i + d.x, j + d.y};
        edge_cell = edge_cell || (inside(nb) && !obstacle_[index(nb)]);
      }
      if (!edge_cell) continue;
      for (const GridCell& d : disk) {
        const GridCell nb{i + d.x, j + d.y};
        if (inside(nb)) blocked_[index(nb)] = 1;
      }
    }
  }
}

std::optional<GridCell> DrivableGrid::cell_of(double x, double y) const {
  const double fx = std::floor((x - origin_.x()) / settings_.cell);
  const double fy = std::floor((y - origin_.y()) / settings_.cell);
  if (!(fx >= 0 && fy >= 0 && fx < nx_ && fy < ny_)) return std::nullopt;
  return GridCell{static_cast<std::int32_t>(fx), static_cast<std::int32_t>(fy)};
}

Eigen::Vector3d DrivableGrid::center(const GridCell& c) const {
  return {origin_.x() + (c.x + 0.5) * settings_.cell, origin_.y() + (c.y + 0.5) * settings_.cell, surface(c)};
}

bool DrivableGrid::step_ok(const GridCell& a, const GridCell& b) const {
  return inside(b) && !blocked(b) && std::abs(surface(a) - surface(b)) <= settings_.max_step;
}

bool DrivableGrid::passable(const GridCell& a, const GridCell& b) const {
  if (!inside(a) || blocked(a) || !step_ok(a, b)) return false;
  if (a.x == b.x || a.y == b.y) return true;
  const GridCell c1{b.x, a.y}, c2{a.x, b.y};
  return step_ok(a, c1) && step_ok(c1, b) && step_ok(a, c2) && step_ok(c2, b);
}

}  // namespace sarmap::eval
