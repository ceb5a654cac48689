#include "engine/segments/segment_settings.hpp"

#include <cmath>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::segments {
namespace {

void require(bool ok, const char* what) {
  if (!ok) throw Error(ErrorCode::InvalidArgument, std::string("segment settings: ") + what);
}

}  // namespace

void validate(const SegmentSettings& s) {
  // Written as !(x > 0) so NaN fails too.
  require(s.voxel >= 0 && std::isfinite(s.voxel), "voxel must be >= 0 (0 = input already thinned)");
  require(s.voxel == 0 || s.voxel >= 1e-3, "voxel must be at least 0.001 m (or 0)");
  require(s.distance_threshold > 0 && std::isfinite(s.distance_threshold), "distance_threshold must be > 0");
  require(s.confidence > 0 && s.confidence < 1, "confidence must be in (0, 1)");
  require(s.max_iterations >= 1, "max_iterations must be >= 1");
  require(s.min_points >= 3, "min_points must be >= 3");
  require(s.cluster_radius > 0 && std::isfinite(s.cluster_radius), "cluster_radius must be > 0");
  require(s.merge_angle_deg >= 0 && s.merge_angle_deg < 90, "merge_angle_deg must be in [0, 90)");
  require(s.merge_overlap_angle_deg >= s.merge_angle_deg && s.merge_overlap_angle_deg < 90,
          "merge_overlap_angle_deg must be in [merge_angle_deg, 90)");
  require(s.merge_offset >= 0 && std::isfinite(s.merge_offset), "merge_offset must be >= 0");
  require(s.merge_gap >= 0 && std::isfinite(s.merge_gap), "merge_gap must be >= 0");
  require(s.max_range >= 0 && std::isfinite(s.max_range), "max_range must be >= 0 (0 = no limit)");
  require(s.closer_view_ratio > 0 && s.closer_view_ratio <= 1, "closer_view_ratio must be in (0, 1]");
  require(s.max_search_rounds >= 1 && s.max_search_rounds <= 255, "max_search_rounds must be in [1, 255]");
}

bool is_segmented_class(ClassId label) {
  return label == ClassId::Terrain || label == ClassId::Wall || label == ClassId::InclinedRamp ||
         label == ClassId::FlatRamp;
}

}  // namespace sarmap::segments
