#include "engine/core/class_colors.hpp"

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"

namespace sarmap {

void paint_class_colors(PointBuffer& points) {
  if (!points.has_labels()) {
    throw Error(ErrorCode::InvalidArgument, "class colours need a label per point, and these points have none");
  }
  points.enable_colors();
  const auto labels = points.labels();
  const auto red = points.red(), green = points.green(), blue = points.blue();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Rgb c = class_info(class_from_value(labels[i]).value_or(ClassId::Unknown)).color;
    red[i] = c.r;
    green[i] = c.g;
    blue[i] = c.b;
  }
}

}  // namespace sarmap
