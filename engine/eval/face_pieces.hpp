// Splits an arena face into the pieces that the other solids leave open: a
// wall standing against another wall's face hides a strip of it and may cut
// it in two, which a map rightly sees as two surfaces.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/sim/arena.hpp"
#include "engine/sim/arena_mesh.hpp"

namespace sarmap::eval {

struct TruthFace;

// A convex solid as the planes of its faces (n . x + d <= 0 inside).
struct ConvexSolid {
  std::vector<std::pair<Eigen::Vector3d, double>> planes;
  Eigen::AlignedBox3d box;  // its axis-aligned extent

  bool contains(const Eigen::Vector3d& p) const;
};

// The solid of a wall, inclined ramp, flat ramp or box from its mesh (those
// standing on the floor are closed by the floor's plane); none for meshes,
// which need not be convex.
std::optional<ConvexSolid> element_solid(const sim::ArenaElement& element, const sim::ClassedMesh& mesh);

// Orthonormal in-plane axes with u, v, n right-handed, so that counter-
// clockwise in (u, v) is counter-clockwise seen from the normal's side.
std::pair<Eigen::Vector3d, Eigen::Vector3d> in_plane_axes(const Eigen::Vector3d& normal);

// The face sampled every `step` metres: samples just in front of it that lie
// inside one of `others` are hidden. Without hidden samples, the face itself;
// else one piece per 4-connected group of open samples of at least
// `min_area` m^2: the face's outline clipped to the group's extent, its area
// and centre those of the group's samples (pieces field set).
std::vector<TruthFace> open_pieces(const TruthFace& face, std::span<const ConvexSolid> others, double step = 0.02,
                                   double min_area = 0.005);

}  // namespace sarmap::eval
