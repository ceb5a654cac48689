// Merging another segment map into this one (two robots' or two runs' maps of
// one map frame): the other map's stored points arrive as its scans brought
// them, scan by scan with each scan's origin, so its surfaces join this map's
// by the rule every new scan's points follow. Replaying the points rather
// than splicing segments keeps one place that decides when two segments are
// one surface.
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/metres_text.hpp"
#include "engine/segments/segment_map.hpp"

namespace sarmap::segments {
namespace {

// The stored points of `indices` as a labelled buffer.
PointBuffer labelled_points(const LabelledVoxels& voxels, const std::vector<std::uint32_t>& indices) {
  PointBuffer points;
  points.enable_labels();
  points.resize(indices.size());
  for (std::size_t i = 0; i < indices.size(); ++i) {
    const std::uint32_t k = indices[i];
    points.x()[i] = voxels.x[k];
    points.y()[i] = voxels.y[k];
    points.z()[i] = voxels.z[k];
    points.labels()[i] = voxels.label[k];
  }
  return points;
}

}  // namespace

SegmentUpdate SegmentMap::merge(const SegmentMap& other, const Pose& other_to_this) {
  if (&other == this) throw Error(ErrorCode::InvalidArgument, "segments: a map cannot be merged into itself");
  if (other.voxels_.voxel() != voxels_.voxel()) {
    throw Error(ErrorCode::InvalidArgument, "segments: cannot merge a map thinned to " +
                                                metres_text(other.settings_.voxel) +
                                                " voxels into one thinned to " + metres_text(settings_.voxel));
  }
  // Stored points grouped by the scan that stored them; points of a
  // reclassified region that no scan saw come last, as a reclassification.
  std::vector<std::vector<std::uint32_t>> by_scan(other.origins_.size());
  std::vector<std::uint32_t> without_scan;
  for (std::uint32_t k = 0; k < other.voxels_.size(); ++k) {
    const std::uint32_t scan = other.voxels_.scan[k];
    (scan < by_scan.size() ? by_scan[scan] : without_scan).push_back(k);
  }
  const auto moved = [&](const std::vector<std::uint32_t>& indices) {
    PointBuffer points = labelled_points(other.voxels_, indices);
    other_to_this.apply(points);
    return points;
  };
  SegmentUpdate total;
  for (std::size_t scan = 0; scan < by_scan.size(); ++scan) {
    if (by_scan[scan].empty()) continue;
    total += integrate(moved(by_scan[scan]), other_to_this * other.origins_[scan]);
  }
  if (!without_scan.empty()) total += reclassify(moved(without_scan));
  return total;
}

}  // namespace sarmap::segments
