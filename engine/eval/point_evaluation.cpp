#include "engine/eval/point_evaluation.hpp"

#include <string>

#include "engine/core/error.hpp"

namespace sarmap::eval {

PointEvaluation evaluate_points(const PointBuffer& points, std::string_view source) {
  const std::string where(source);
  if (!points.has_labels()) throw Error(ErrorCode::InvalidData, where + ": no `label` property (sarmap's prediction)");
  if (!points.has_gt_labels()) {
    throw Error(ErrorCode::InvalidData, where + ": no `gt_label` property (ground truth) to score against");
  }
  PointEvaluation e;
  e.points = points.size();
  const auto predicted = points.labels();
  const auto truth = points.gt_labels();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto p = class_from_value(predicted[i]);
    const auto t = class_from_value(truth[i]);
    if (!p || !t) {
      throw Error(ErrorCode::InvalidData, where + ": point " + std::to_string(i) + " has label " +
                                              std::to_string(predicted[i]) + " / gt_label " +
                                              std::to_string(truth[i]) + ", not a class id (0-" +
                                              std::to_string(kClassCount - 1) + ")");
    }
    if (*t == ClassId::Unknown) continue;
    ++e.scored;
    if (*p == ClassId::Unknown) ++e.unlabelled;
    e.confusion.add(*t, *p);
  }
  return e;
}

}  // namespace sarmap::eval
