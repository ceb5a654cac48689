// The check the rules after the network (wall bands, ramp side faces, wall
// feet) make before grouping a scan's points by column: a point with a
// non-finite coordinate has no column, so the scan is refused, naming the
// first such point, rather than the point being skipped unseen.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>

#include "engine/core/error.hpp"
#include "engine/core/point_buffer.hpp"

namespace sarmap {

// Throws sarmap::Error (InvalidArgument) "<rule>: point <i> is not finite"
// for the first point with a NaN or infinite coordinate.
inline void require_finite_points(const PointBuffer& points, std::string_view rule) {
  const auto xs = points.x(), ys = points.y(), zs = points.z();
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (!std::isfinite(xs[p]) || !std::isfinite(ys[p]) || !std::isfinite(zs[p])) {
      throw Error(ErrorCode::InvalidArgument, std::string(rule) + ": point " + std::to_string(p) + " is not finite");
    }
  }
}

}  // namespace sarmap
