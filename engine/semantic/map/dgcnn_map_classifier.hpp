// Labels scans by classifying the accumulated map instead of each scan: the
// scan's points join a labelled point map (one point per small cell), the
// map's blocks that grew enough are classified with every map point in them
// as input, their scores replace the block's earlier ones in its points, and
// the scan's points take the classes of the map points they fall on. A
// surface seen by many scans is classified a few times, each time from a
// fuller view than one scan gives.
//
// Labels therefore arrive late: a point whose block has not reached its
// minimum yet stays unknown, and a point's class can change when its block is
// classified again. What depends on them: the metric map fuses the classes
// each scan has when it is integrated (later scans of the same voxels fuse
// the newer ones); the kept semantic points and the segments take theirs from
// this map when asked (relabel()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/point_buffer.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/semantic/dgcnn/class_probabilities.hpp"
#include "engine/semantic/dgcnn/dgcnn_model.hpp"
#include "engine/semantic/dgcnn/dgcnn_workspace_pool.hpp"
#include "engine/semantic/map/class_delays.hpp"
#include "engine/semantic/map/labelled_point_map.hpp"
#include "engine/semantic/map/map_block_schedule.hpp"

namespace sarmap {

struct DgcnnMapClassifierSettings {
  double cell = 0.025;           // metres: one map point per cell
  double stride = 0.0;           // metres between block origins; <= 0: kDefaultStrideFraction x the block size
  std::size_t min_points = 100;  // map points a block needs before it is first classified
  double growth = 0.25;          // a block is classified again once it has grown by this fraction
  std::size_t min_new_points = 512;  // ... and by at least this many points (chosen on the validation arenas)
  // A map point still without a class (its own or a neighbour's) this many
  // scans after it arrived has its most central block classified, however
  // few new points that block holds: an isolated surface, a LiDAR's far
  // points, would otherwise wait for min_new_points. 0: points wait.
  std::size_t max_wait_scans = 20;
  std::uint64_t seed = 1;        // sampling seed; results do not depend on threads
};

struct DgcnnMapClassifyStats {
  std::size_t blocks = 0;          // blocks classified for this scan
  std::size_t map_points_added = 0;
  std::size_t unlabelled = 0;      // scan points whose map point has no class yet
};

class DgcnnMapClassifier {
 public:
  // Throws sarmap::Error for a model without preprocessing metadata, a class
  // count that disagrees with the network, or bad settings.
  DgcnnMapClassifier(const DgcnnModel& model, const DgcnnMapClassifierSettings& settings);

  // Adds the scan's points to the map, classifies the blocks that are ready,
  // then sets the scan's labels and one score channel per sarmap class
  // (class_probabilities()) from the map. Runs the blocks in parallel in the caller's TBB arena; the
  // result does not depend on the thread count.
  DgcnnMapClassifyStats classify(PointBuffer& scan);
  // Classifies every block still holding points no classification has seen
  // (when the scans end: blocks wait for growth or a quiet scan otherwise);
  // returns how many. changed_points() then lists their points.
  std::size_t finish();
  // Lets go of every map point where forget(x, y, z) is true (the region a
  // bounded map dropped), with its place in the blocks; the blocks keep the
  // scores of the rest, so no point's class changes. Returns how many.
  template <class Predicate>
  std::size_t forget(Predicate&& forget);
  // Takes `other`'s labelled point map, carried into this one's frame
  // (LabelledPointMap::merge): what a merged Mapper's kept points and
  // voxels take their classes from. The block schedule stays this map's: a
  // merged map is classified no further. Throws as LabelledPointMap::merge.
  void merge(const DgcnnMapClassifier& other, const Pose& other_to_this);
  // Sets labels and score channels of `points` from the map points of their
  // cells (unknown and zeros where there is none or it has no class yet),
  // without adding them. A point
  // whose cell holds no map point (cells of a map merged from another frame
  // do not line up with its points) borrows its classified neighbour's
  // class, as an unclassified map point does. Returns how many stay unknown.
  std::size_t relabel(PointBuffer& points) const;

  const LabelledPointMap& map() const { return map_; }
  // The sarmap class of each score channel of the map's points (one per
  // model logit; several may share a class).
  const std::vector<ClassId>& channel_classes() const { return model_.metadata().classes; }
  // Sums the map's per-logit scores per sarmap class; labels are the arg-max
  // of those sums, as the per-scan classifier's are.
  const ClassProbabilities& class_probabilities() const { return class_probabilities_; }
  // The class of map point p by that rule (its own scores or its classified
  // neighbour's: scored_point), or Unknown while it has none.
  ClassId map_point_class(std::uint32_t p) const;
  const MapBlockSchedule& blocks() const { return schedule_; }
  std::size_t blocks_classified() const { return blocks_classified_; }
  // The map points the last classify() added or classified again (possibly
  // with repeats): what holds classes that changed.
  const std::vector<std::uint32_t>& changed_points() const { return changed_; }
  // How many scans each map point waited for its class (ClassDelays), and
  // the points still waiting.
  const ClassDelays& class_delays() const { return delays_; }

  void save_state(StateWriter& out) const;
  void load_state(StateReader& in);

 private:
  std::vector<std::uint8_t> classify_block(const MapBlock& block, DgcnnWorkspace& workspace) const;
  // Adds to `ready` (in (j, i) order, as MapBlockSchedule::ready() gives)
  // the blocks of the map points that have now waited max_wait_scans.
  void add_blocks_of_long_waiting_points(std::vector<MapBlock*>& ready);
  // Classifies the blocks in parallel and fuses their scores in order.
  std::size_t classify_blocks(const std::vector<MapBlock*>& blocks);
  std::size_t label_points(PointBuffer& points, std::span<const std::uint32_t> map_points) const;
  // The waiting map points (from index `from` of the list) that have a class now stop waiting.
  void settle_class_delays(std::size_t from = 0);

  const DgcnnModel& model_;
  DgcnnMapClassifierSettings settings_;
  ClassProbabilities class_probabilities_;
  LabelledPointMap map_;
  MapBlockSchedule schedule_;
  std::size_t blocks_classified_ = 0;
  std::vector<std::uint32_t> changed_;
  std::uint32_t scans_ = 0;  // classify() calls
  ClassDelays delays_;
  // Forward-pass buffers kept between scans: allocating and zeroing them
  // for every scan's blocks showed in a whole run's time.
  DgcnnWorkspacePool workspaces_;
};

template <class Predicate>
std::size_t DgcnnMapClassifier::forget(Predicate&& forget) {
  const PointBuffer& points = map_.points();
  std::vector<std::uint8_t> keep(points.size());
  std::size_t forgotten = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    keep[p] = forget(points.x()[p], points.y()[p], points.z()[p]) ? 0 : 1;
    forgotten += 1 - keep[p];
  }
  if (forgotten == 0) return 0;
  const std::vector<std::uint32_t> renumbered = map_.keep_only(keep);
  schedule_.renumber(renumbered, model_.classes());
  delays_.renumber(renumbered);
  changed_.clear();
  return forgotten;
}

}  // namespace sarmap
