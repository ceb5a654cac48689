// Merging another Mapper's maps into this one: two robots' runs in one map
// frame, or the parts of one sequence mapped apart. Every map merges by the
// rule that map already follows for new data (docs/architecture.md, "Merging
// maps"); the topological map is rebuilt from the merged segments.
#include <string>

#include "engine/core/error.hpp"
#include "engine/core/metres_text.hpp"
#include "engine/metric/map_merge.hpp"
#include "engine/metric/map_transform.hpp"
#include "engine/pipeline/mapper.hpp"

namespace sarmap::pipeline {
namespace {

void require_same(double here, double other, const char* what) {
  if (here == other) return;
  throw Error(ErrorCode::InvalidArgument, std::string("merge: cannot merge maps with ") + what + " " +
                                              metres_text(other) + " into maps with " + what + " " +
                                              metres_text(here));
}

bool is_identity(const Pose& pose) {
  return pose.rotation() == Eigen::Matrix3d::Identity() && pose.translation() == Eigen::Vector3d::Zero();
}

}  // namespace

MapperMergeCounts Mapper::merge(Mapper& other, const Pose& other_to_this) {
  if (&other == this) throw Error(ErrorCode::InvalidArgument, "merge: a Mapper cannot be merged into itself");
  // Everything that could refuse the merge is checked before any map changes.
  require_same(config_.semantic_points_voxel, other.config_.semantic_points_voxel, "semantic_points_voxel");
  require_same(segments_.settings().voxel, other.segments_.settings().voxel, "a segment voxel of");
  if (classifier_->name() != other.classifier_->name()) {
    throw Error(ErrorCode::InvalidArgument,
                "merge: cannot merge maps classified by " + std::string(other.classifier_->name()) +
                    " into maps classified by " + std::string(classifier_->name()));
  }
  metric::check_mergeable(map_, other.map_);
  // The classifier of the accumulated map hands its last blocks' classes to
  // the metric map at finish(): both maps must hold them before they merge.
  finish();
  other.finish();
  // First: the only part of the merge that can still refuse (another cell
  // size or class count of the labelled point map) changes nothing when it does.
  classifier_->merge(*other.classifier_, other_to_this);
  MapperMergeCounts counts;
  const bool moved = !is_identity(other_to_this);
  counts.metric = moved ? metric::merge_into(map_, metric::transformed_map(other.map_, other_to_this))
                        : metric::merge_into(map_, other.map_);
  stats_ += other.stats_;
  blocks_dropped_ += other.blocks_dropped_;
  const std::size_t points_before = semantic_points_.size();
  if (moved) {
    PointBuffer points = other.semantic_points_;
    other_to_this.apply(points);
    keep_semantic_points(points);
  } else {
    keep_semantic_points(other.semantic_points_);
  }
  counts.semantic_points_added = semantic_points_.size() - points_before;
  counts.segments = segments_.merge(other.segments_, other_to_this);
  counts.topo = topo_.update(segments_, map_);
  profile_.append(other.profile_);
  merged_ = true;
  return counts;
}

}  // namespace sarmap::pipeline
