// Where the topological map's nodes may stand, from the segments: on terrain
// and platform tops at the points of a fixed lattice (so nodes are at least a
// lattice pitch apart and never move as segments grow), at its centre when a
// segment is too small for any lattice point; for an inclined ramp, one node
// just off its foot on the floor and one just past its top on whatever deck
// it leads to, so that no node stands on a slope (the thesis's rule: a robot
// stopped on a slope slides). Every place is on a free cell of the
// traversability grid: on seen ground, clear of walls by the robot's radius.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "engine/segments/segment.hpp"
#include "engine/topo/topo_settings.hpp"
#include "engine/topo/traversability_grid.hpp"
#include "engine/topo/wall_scene.hpp"

namespace sarmap::topo {

enum class NodeKind : std::uint8_t { Terrain, FlatRamp, RampFoot, RampTop };

// "terrain", "flat_ramp", "ramp_foot", "ramp_top" (graph.json's kind).
std::string_view to_string(NodeKind kind);

// What makes a place the same place from one update to the next: a lattice
// point at a height level, or a segment's centre / ramp foot / ramp top.
struct PlaceKey {
  enum class Type : std::uint8_t { Lattice, Centre, Foot, Top } type = Type::Lattice;
  std::int64_t a = 0, b = 0, c = 0;  // lattice: i, j, height level; the others: the segment id
  friend bool operator==(const PlaceKey&, const PlaceKey&) = default;
};

struct Place {
  PlaceKey key;
  Eigen::Vector3d position;  // on the surface
  NodeKind kind = NodeKind::Terrain;
  std::uint32_t segment = 0;  // the segment it stands on (the ramp's, for foot and top)
};

// Places in a deterministic order (segments in the given order, lattice
// points row by row).
std::vector<Place> place_nodes(const std::vector<const segments::Segment*>& segments, const TraversabilityGrid& grid,
                               const WallScene& walls, const TopoSettings& settings);

}  // namespace sarmap::topo
