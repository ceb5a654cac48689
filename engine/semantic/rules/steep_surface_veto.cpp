#include "engine/semantic/rules/steep_surface_veto.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/semantic/rules/class_move.hpp"
#include "engine/semantic/surface_normals.hpp"

namespace sarmap {

void validate(const SteepSurfaceVetoSettings& settings) {
  if (!(settings.cell >= 0.01) || !std::isfinite(settings.cell)) {
    throw Error(ErrorCode::InvalidArgument, "steep surface veto: cell size must be at least 0.01 m");
  }
  if (!(settings.min_slope_deg > 0.0 && settings.min_slope_deg <= 90.0)) {
    throw Error(ErrorCode::InvalidArgument, "steep surface veto: the slope must be in (0, 90] degrees, got " +
                                                std::to_string(settings.min_slope_deg));
  }
}

std::size_t veto_steep_inclined_ramps(PointBuffer& points, const SteepSurfaceVetoSettings& settings) {
  validate(settings);
  if (!settings.enabled || !points.has_labels()) return 0;
  const auto inclined = static_cast<std::uint8_t>(ClassId::InclinedRamp);
  const auto labels = points.labels();
  if (std::find(labels.begin(), labels.end(), inclined) == labels.end()) return 0;

  SurfaceNormalSettings fit;
  fit.cell = settings.cell;
  fit.min_points = settings.min_points;
  // Always the pooled neighbourhood: a wall band seen at the sensor's range
  // is noisy enough to look curved, and its own cell alone is too few points
  // to say which way it faces.
  fit.max_curvature = 1.0;
  const SurfaceNormals normals = estimate_surface_normals(points, fit);

  const double max_nz = std::cos(settings.min_slope_deg * std::numbers::pi / 180.0);
  const std::size_t channels = points.score_count();
  const std::size_t wall = points.find_score("wall"), other = points.find_score("other");
  const bool scored = wall < channels && other < channels;
  ClassMove to_wall(points, ClassId::InclinedRamp, ClassId::Wall);
  ClassMove to_other(points, ClassId::InclinedRamp, ClassId::Other);
  std::size_t changed = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (labels[p] != inclined || normals.valid[p] == 0 || !(normals.nz[p] <= max_nz)) continue;
    const bool other_wins = scored && points.score(other)[p] > points.score(wall)[p];
    (other_wins ? to_other : to_wall).apply(p);
    ++changed;
  }
  return changed;
}

}  // namespace sarmap
