// The arena's true planar faces (the floor, wall faces, ramp decks, platform
// tops and their sides) found from its meshes, less what other solids hide,
// and how much of each the sensor saw: what the segment figures match the
// run's segments against.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/ground_truth_grid.hpp"

namespace sarmap::eval {

// Floor, WallFace (the two faces of a wall parallel to its from -> to
// direction), RampDeck (an inclined ramp's sloped face) and PlatformTop (a
// flat ramp's top) are the faces a map must find. Side faces (wall ends and
// tops, ramp sides and backs, platform sides) are real surfaces a segment may
// lie on, but small or seen edge-on, so nobody counts them as missed.
enum class FaceKind { Floor, WallFace, RampDeck, PlatformTop, Side };

// "floor", "wall_face", "ramp_deck", "platform_top", "side".
std::string_view face_kind_name(FaceKind kind);

struct TruthFace {
  std::size_t mesh = 0;                // index in sim::arena_meshes(arena)
  std::optional<std::size_t> element;  // index in arena.elements; none for the floor
  std::string name;                    // the mesh's name: "floor", "elements[4] (inclined_ramp)"
  FaceKind kind = FaceKind::Side;
  // A face that another element cuts in two (a wall standing against it) is
  // `pieces` faces, numbered by `piece`.
  std::size_t piece = 0, pieces = 1;
  ClassId label = ClassId::Unknown;
  // n . x + offset = 0, with n the unit normal out of the solid (up for the floor).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0;
  // Convex outline in the plane, counter-clockwise seen from the normal's side.
  std::vector<Eigen::Vector3d> polygon;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // centroid of the open area
  double area_m2 = 0;                                // open area
  double slope_deg = 0;  // from horizontal

  // Whether a map is expected to find it (every kind but Side).
  bool counted() const { return kind != FaceKind::Side; }
  double distance(const Eigen::Vector3d& p) const { return normal.dot(p) + offset; }
  // Whether p projected onto the plane lies in the outline grown by margin (metres).
  bool contains(const Eigen::Vector3d& p, double margin) const;
};

// Every face of the floor, walls, inclined ramps and flat ramps, in mesh
// order, less the parts inside other elements' solids (open_pieces). Boxes and
// meshes give none: their class is other, which the segment stage does not
// segment; boxes still hide what they stand against.
std::vector<TruthFace> truth_faces(const sim::Arena& arena);

// The fraction of the face seen by the sensor: the face is sampled on a grid
// of the truth grid's resolution and a sample counts when the voxel on either
// side of it (a face on a voxel boundary is split between the two) is an
// observed occupied voxel. 0 for a grid without visibility (compute_free off).
double seen_fraction(const TruthFace& face, const sim::GroundTruthGrid& grid);

}  // namespace sarmap::eval
