// Per-point scoring of a classified cloud: sarmap's prediction (`label`)
// against the ground truth kept beside it (`gt_label`). Points without a
// ground-truth class (gt_label 0) cannot be scored and are only counted;
// points the classifier could not label (label 0) count as wrong.
#pragma once

#include <cstddef>
#include <string_view>

#include "engine/core/point_buffer.hpp"
#include "engine/eval/confusion_matrix.hpp"

namespace sarmap::eval {

struct PointEvaluation {
  ConfusionMatrix confusion;
  std::size_t points = 0;      // in the cloud
  std::size_t scored = 0;      // with a ground-truth class
  std::size_t unlabelled = 0;  // scored points predicted as class 0
};

// Throws sarmap::Error(InvalidData) naming `source` when the cloud lacks
// label or gt_label, or holds a value that is not a class id.
PointEvaluation evaluate_points(const PointBuffer& points, std::string_view source);

}  // namespace sarmap::eval
