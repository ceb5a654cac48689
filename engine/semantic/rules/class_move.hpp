// Moving a point from one class to another after the network, for the rules
// that correct its labels (steep-surface veto, wall bands, ramp side
// faces, wall feet). The old class's score moves with the label to the new class's
// score, when the points carry both channels: the label stays the scores'
// arg-max, and the map, which fuses scores where a point has them, sees the
// same change.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/classes.hpp"
#include "engine/core/point_buffer.hpp"

namespace sarmap {

class ClassMove {
 public:
  ClassMove(PointBuffer& points, ClassId from, ClassId to)
      : points_(points),
        to_(static_cast<std::uint8_t>(to)),
        from_score_(points.find_score(std::string(class_info(from).name))),
        to_score_(points.find_score(std::string(class_info(to).name))),
        scored_(from_score_ < points.score_count() && to_score_ < points.score_count()) {}

  // Relabels point p (whatever its label) and moves its score.
  void apply(std::size_t p) {
    points_.labels()[p] = to_;
    if (scored_) {
      points_.score(to_score_)[p] += points_.score(from_score_)[p];
      points_.score(from_score_)[p] = 0.0f;
    }
  }

 private:
  PointBuffer& points_;
  std::uint8_t to_;
  std::size_t from_score_, to_score_;
  bool scored_;
};

}  // namespace sarmap
