// The side faces of inclined ramps, which the network calls wall. A wedge
// ramp's sides are vertical triangles under its sloped deck; the arenas'
// ground truth (and a rescue team reading the map) count them as part of
// the ramp, but one block's view of a vertical face looks like any wall's.
// In held-out arenas most of the ramp points the network got wrong were
// these faces: steep (60-90 degrees), 0-0.5 m high, far from every wall.
//
// What tells them from a wall is what lies above: a side face is under the
// deck's edge, so within a hand's width horizontally there is ramp deck a
// little higher up; a wall next to a ramp shows only above the ramp's
// surface (the ramp hides the wall below it). So a point labelled wall
// becomes inclined ramp when deck lies within `radius` horizontally and
// between min_rise and max_rise above it. Deck is what the network labelled
// inclined ramp on a plane gentle enough to be one. The network calls some
// side faces other (the side of a box) instead: those points become ramp
// the same way (its A/B: docs/perf-history.md).
//
// A camera low beside a ramp sees its side but rarely the deck above, so the
// decks are remembered across a sequence's scans: RampDeckMemory keeps, per
// column of a horizontal grid, the height span of every deck point seen.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/flat_key_map.hpp"
#include "engine/core/point_buffer.hpp"
#include "engine/core/state_stream.hpp"

namespace sarmap {

struct RampSideSettings {
  bool enabled = true;
  double radius = 0.15;    // metres, horizontal reach to the deck above (the grid's column size)
  double min_rise = 0.03;  // the deck at least this much higher (noise on a flat join)
  double max_rise = 1.0;   // and at most this much (the arenas' ramps rise at most 1 m)
  // Deck: an inclined-ramp label on a plane no steeper than this (the
  // arenas' ramps are 10-25 degrees; a wall band the network took for a ramp
  // is steeper) ...
  double deck_max_slope_deg = 35.0;
  // ... and planar: a wall's foot fitted together with the floor gives a
  // gentle normal too, but with a curvature (smallest eigenvalue over their
  // sum) well above this.
  double deck_max_curvature = 0.02;
  double normal_cell = 0.1;     // metres; the deck's plane is fitted over 3 x 3 x 3 cells
  std::size_t min_points = 10;  // fewer around a deck point: its plane is unknown, it is no deck
};

class RampDeckMemory {
 public:
  // Throws sarmap::Error (InvalidArgument) for a radius or cell under 1 cm,
  // rises not 0 <= min_rise < max_rise, a slope outside (0, 90] or a
  // negative curvature.
  explicit RampDeckMemory(const RampSideSettings& settings);

  // Remembers the scan's deck points (world frame, labelled), then relabels
  // as inclined ramp the points labelled wall or other that stand under a
  // deck seen in this scan or an earlier one. Each such point's "wall" (or
  // "other") score moves to its "inclined_ramp" score when both channels
  // exist (so the label stays the scores' arg-max and the map's score
  // fusion agrees). Returns how many
  // points changed; nothing when disabled or unlabelled. Throws
  // sarmap::Error (InvalidArgument, like the normals) for a non-finite point.
  std::size_t label_side_faces(PointBuffer& points);
  // The same with the decks already remembered, remembering none of
  // `points`' own (points whose scans were seen: the kept points relabelled).
  std::size_t label_under_known_decks(PointBuffer& points) const;

  // Forgets every deck (a new sequence).
  void clear() { decks_.clear(); }
  // Grid columns holding deck.
  std::size_t columns() const { return decks_.size(); }

  // The decks seen so far, for a checkpoint (engine/core/state_stream.hpp).
  void save_state(StateWriter& out) const;
  // Replaces the decks with saved ones. Throws sarmap::Error (Parse) naming
  // the offset; unchanged then.
  void load_state(StateReader& in);

 private:
  struct HeightSpan {
    float low, high;  // lowest and highest deck point in the column
  };
  // The deck spans of the 3 x 3 columns around column (cx, cy).
  struct DecksAround {
    HeightSpan spans[9];
    int count = 0;
  };
  void remember_decks(const PointBuffer& points);
  DecksAround decks_around(std::int64_t cx, std::int64_t cy) const;
  bool under_a_deck(const DecksAround& decks, double z) const;

  RampSideSettings settings_;
  // Each deck column's height span, by its key (grid_keys::column_key).
  FlatKeyMap<HeightSpan> decks_;
};

// One scan on its own: RampDeckMemory(settings).label_side_faces(points).
std::size_t label_ramp_side_faces(PointBuffer& points, const RampSideSettings& settings);

}  // namespace sarmap
