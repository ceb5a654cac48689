#include "engine/topo/node_placement.hpp"

#include <cmath>
#include <numbers>

#include "engine/segments/walkable.hpp"

namespace sarmap::topo {
namespace {

// Heights are told apart in levels of this size, so a floor lattice point and
// a platform's above it are two places.
constexpr double kLevel = 0.1;
// Inclined ramps flatter than this are floors, steeper ones ramps.
constexpr double kRampMinSlopeDeg = 5.0;

// A free cell, clear of walls, whose surface is the place's own: at its height
// (not a deck above or a floor below) and of its class. No place is ever on a
// slope: the low end of a ramp is within a step of the floor, but its class
// gives it away.
bool free_place(const TraversabilityGrid& t, const WallScene& walls, const Eigen::Vector3d& p, double max_step,
                ClassId surface) {
  const GridCell cell = t.grid.cell_at(p.head<2>());
  if (!t.grid.contains(cell) || t.grid.at(cell) != CellState::Free) return false;
  const ClassId ground = t.ground_class[t.grid.index_of(cell)];
  const bool right_class = surface == ClassId::Unknown ? ground != ClassId::InclinedRamp : ground == surface;
  return right_class && std::abs(t.ground_at(cell) - p.z()) <= max_step && walls.clear(p);
}

// Offsets a lattice point may take, nearest first: rings of 8 directions
// every `step` out to a third of the pitch.
std::vector<Eigen::Vector2d> nudges(double pitch, double step) {
  std::vector<Eigen::Vector2d> out{Eigen::Vector2d::Zero()};
  for (double r = step; r <= pitch / 3 + 1e-9; r += step) {
    for (int k = 0; k < 8; ++k) {
      const double a = k * std::numbers::pi / 4;
      out.emplace_back(r * std::cos(a), r * std::sin(a));
    }
  }
  return out;
}

std::int64_t level_of(double z) { return static_cast<std::int64_t>(std::llround(z / kLevel)); }

// A ramp's low or high edge midpoint and the horizontal direction away from
// the slope there.
struct RampEnd {
  Eigen::Vector3d edge;
  Eigen::Vector2d outwards;
};

RampEnd ramp_end(const segments::Segment& ramp, bool low) {
  const Eigen::Vector3d& n = ramp.plane.normal;
  // A ramp's normal leans downhill.
  const Eigen::Vector2d downhill = n.head<2>().normalized();
  const Eigen::Vector3d downhill_in_plane =
      (Eigen::Vector3d(downhill.x(), downhill.y(), 0) - n * n.head<2>().dot(downhill)).normalized();
  const auto& r = ramp.rectangle;
  const int along = std::abs(r.axes[0].dot(downhill_in_plane)) >= std::abs(r.axes[1].dot(downhill_in_plane)) ? 0 : 1;
  const double sign = (r.axes[along].dot(downhill_in_plane) >= 0 ? 1.0 : -1.0) * (low ? 1.0 : -1.0);
  return {r.center + sign * r.half_extents[along] * r.axes[along], low ? downhill : Eigen::Vector2d(-downhill)};
}

}  // namespace

std::string_view to_string(NodeKind kind) {
  switch (kind) {
    case NodeKind::Terrain: return "terrain";
    case NodeKind::FlatRamp: return "flat_ramp";
    case NodeKind::RampFoot: return "ramp_foot";
    case NodeKind::RampTop: return "ramp_top";
  }
  return "?";
}

std::vector<Place> place_nodes(const std::vector<const segments::Segment*>& segments, const TraversabilityGrid& t,
                               const WallScene& walls, const TopoSettings& settings) {
  std::vector<Place> places;
  const double s = settings.node_spacing;
  const double res = t.grid.resolution();
  const std::vector<Eigen::Vector2d> offsets = nudges(s, 2 * res);
  for (const segments::Segment* seg : segments) {
    if (!segments::is_walkable(*seg)) continue;
    const bool flat_ramp = seg->label == ClassId::FlatRamp;
    if ((seg->label == ClassId::Terrain || flat_ramp) && seg->slope_deg <= settings.max_slope_deg) {
      const NodeKind kind = flat_ramp ? NodeKind::FlatRamp : NodeKind::Terrain;
      const std::size_t before = places.size();
      const auto i0 = static_cast<std::int64_t>(std::ceil(seg->min.x() / s));
      const auto i1 = static_cast<std::int64_t>(std::floor(seg->max.x() / s));
      const auto j0 = static_cast<std::int64_t>(std::ceil(seg->min.y() / s));
      const auto j1 = static_cast<std::int64_t>(std::floor(seg->max.y() / s));
      for (std::int64_t j = j0; j <= j1; ++j) {
        for (std::int64_t i = i0; i <= i1; ++i) {
          for (const Eigen::Vector2d& offset : offsets) {
            const double x = static_cast<double>(i) * s + offset.x(), y = static_cast<double>(j) * s + offset.y();
            const Eigen::Vector3d p(x, y, segments::height_at(*seg, x, y));
            if (!seg->covers(p, 0) || !free_place(t, walls, p, settings.max_step, seg->label)) continue;
            places.push_back({{PlaceKey::Type::Lattice, i, j, level_of(p.z())}, p, kind, seg->id});
            break;
          }
        }
      }
      if (places.size() == before) {
        const Eigen::Vector3d c = seg->rectangle.center;
        if (free_place(t, walls, c, settings.max_step, seg->label)) places.push_back({{PlaceKey::Type::Centre, seg->id, 0, 0}, c, kind, seg->id});
      }
      continue;
    }
    if (seg->label != ClassId::InclinedRamp || seg->slope_deg < kRampMinSlopeDeg) continue;
    // Foot and top: a robot radius and a cell beyond the ramp's edge, on
    // whatever surface the grid shows there.
    const double off = settings.robot_radius + res;
    for (const bool low : {true, false}) {
      const RampEnd end = ramp_end(*seg, low);
      const Eigen::Vector2d xy = end.edge.head<2>() + off * end.outwards;
      const GridCell cell = t.grid.cell_at(xy);
      const float g = t.ground_at(cell);
      if (std::isnan(g) || std::abs(g - end.edge.z()) > settings.max_step + res) continue;
      const Eigen::Vector3d p(xy.x(), xy.y(), g);
      // Off the ramp: on the floor or a deck, whatever its class, never the slope.
      if (!free_place(t, walls, p, settings.max_step, ClassId::Unknown)) continue;
      places.push_back({{low ? PlaceKey::Type::Foot : PlaceKey::Type::Top, seg->id, 0, 0}, p,
                        low ? NodeKind::RampFoot : NodeKind::RampTop, seg->id});
    }
  }
  return places;
}

}  // namespace sarmap::topo
