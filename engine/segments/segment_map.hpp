// The global segment map: planar segments of terrain, walls, inclined ramps
// and flat ramps that grow as scans arrive. Each scan's labelled points are
// thinned into the map's own voxels; a new point joins the segment whose
// plane and outline it lies on, the rest wait per class until enough gather
// for a plane search (RANSAC, least squares, region growing); new segments
// that continue an old one merge into it (the lower id survives). Points whose
// class changes leave their segment, which is refitted, split or dissolved,
// so a reclassified region is re-derived rather than left stale.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "engine/core/bounds.hpp"
#include "engine/core/classes.hpp"
#include "engine/core/point_buffer.hpp"
#include "engine/core/pose.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/segments/labelled_voxels.hpp"
#include "engine/segments/segment.hpp"
#include "engine/segments/segment_settings.hpp"

namespace sarmap::segments {

// What one call did, for the profile's counters.
struct SegmentUpdate {
  std::size_t points_in = 0;        // labelled points offered
  std::size_t points_rejected = 0;  // beyond the voxel keys' reach
  std::size_t points_far = 0;       // farther from the sensor than max_range
  std::size_t points_new = 0;       // voxels seen for the first time
  std::size_t points_changed = 0;   // stored points relabelled or replaced by a closer view
  std::size_t points_attached = 0;  // points that joined an existing segment
  std::size_t planes_found = 0;     // RANSAC planes
  std::size_t created = 0;          // new segments (split-off parts included)
  std::size_t merged = 0;           // segments merged into another
  std::size_t split = 0;            // parts split off a segment that lost points
  std::size_t removed = 0;          // segments dissolved for lack of points
  std::size_t points_forgotten = 0;  // stored points let go by forget()

  SegmentUpdate& operator+=(const SegmentUpdate& other);
};

class SegmentMap {
 public:
  // Throws sarmap::Error (InvalidArgument) for settings out of range.
  explicit SegmentMap(const SegmentSettings& settings = {});
  ~SegmentMap();
  SegmentMap(SegmentMap&&) noexcept;
  SegmentMap& operator=(SegmentMap&&) noexcept;

  const SegmentSettings& settings() const { return settings_; }

  // Adds one scan's world-frame points, labelled with class ids, seen from
  // `origin`. Points of class unknown, and points farther than max_range
  // from the origin, are skipped. Throws sarmap::Error
  // (InvalidArgument) when the points carry no labels or a point or the
  // origin is not finite.
  SegmentUpdate integrate(const PointBuffer& points, const Eigen::Vector3d& origin);
  // Revised classes for points already mapped (a reclassified block): each
  // point's voxel takes its label outright (a point in an empty voxel is
  // added), and every segment that loses points is refitted, split or
  // dissolved. Same errors as integrate.
  SegmentUpdate reclassify(const PointBuffer& points);
  // Lets go of the stored points for which `forgotten(position)` is true (a
  // bounded map's dropped blocks), so the map's memory follows the region
  // kept: they leave their segments, which are refitted, split or dissolved
  // as after a reclassification, and the point storage shrinks. Segment ids
  // and merge history stay. `forgotten` is called concurrently, once per
  // stored point.
  SegmentUpdate forget(const std::function<bool(const Eigen::Vector3d&)>& forgotten);

  // Merges another map of the same frame and thinning voxel into this one
  // (another robot's or run's segments): its stored points arrive scan by
  // scan, each scan's with that scan's origin, as integrate() takes a new
  // scan, so a segment of `other` that continues one here merges into it by
  // the usual rule and the rest become new segments (new ids). Each stored
  // point brings its voxel's class as one vote; points no scan of `other`
  // saw (a reclassified region) come last, as reclassify() takes them. This
  // map's settings rule (max_range included). Throws sarmap::Error
  // (InvalidArgument) naming both voxel sizes when they differ, or for a map
  // merged into itself. `other_to_this` carries other's frame into this
  // map's (points and scan origins; the identity for maps of one frame).
  SegmentUpdate merge(const SegmentMap& other, const Pose& other_to_this = {});

  // Live segments, in id order.
  std::vector<const Segment*> segments() const;
  std::size_t size() const;
  // The live segment with this id, or nullptr.
  const Segment* find(std::uint32_t id) const;
  // The live segment an id became through merges; nullopt if it dissolved.
  std::optional<std::uint32_t> resolve(std::uint32_t id) const;
  // Merges so far, as (absorbed id, surviving id), in order.
  const std::vector<std::pair<std::uint32_t, std::uint32_t>>& merges() const { return merges_; }

  std::vector<const Segment*> of_class(ClassId label) const;
  // Live segments whose extent overlaps the box.
  std::vector<const Segment*> in_box(const Bounds& box) const;
  // The highest walkable segment (terrain, flat ramp or inclined ramp, less
  // than 45 degrees steep) whose rectangle holds p's vertical projection and
  // whose surface there is at most `max_drop` below p (and not above it by
  // more than the inlier threshold); nullptr if none.
  const Segment* under(const Eigen::Vector3d& p, double max_drop) const;
  // The stored points of a live segment, in insertion order.
  std::vector<Eigen::Vector3f> member_points(std::uint32_t id) const;

  // Thinned points held (all classes).
  std::size_t point_count() const { return voxels_.size(); }
  // Bytes the map holds: its stored points with their votes and key index,
  // every segment's record (members and outline included), the pending
  // lists and the per-point and per-scan arrays, by capacity. The segment
  // stage's per-map state, reported beside the metric map's (profile.json,
  // summary.json): one point per 2.5 cm voxel of every labelled surface.
  std::size_t memory_bytes() const;
  // Points waiting for a plane search, per class id.
  std::array<std::size_t, kClassCount> pending_counts() const;

  // The whole state, for a checkpoint (engine/core/state_stream.hpp): a map
  // loaded from it continues exactly as this one would.
  void save_state(StateWriter& out) const;
  // Replaces this map's state with a saved one (same settings). Throws
  // sarmap::Error (Parse) naming the offset for a stream that does not hold
  // one, leaving this map unchanged.
  void load_state(StateReader& in);

 private:
  struct Record;
  struct Work;
  struct SegmentIndex;

  SegmentUpdate finish(Work& work);
  void queue(Work& work, std::uint32_t point);
  void attach(std::uint32_t point, std::uint32_t id);
  void detach(std::uint32_t point);
  void add_pending(std::uint32_t point, ClassId label, Work& work);
  SegmentIndex index_segments(double margin) const;
  // Per point, the segment of its class whose plane is nearest and at most
  // max_distance away, with the point on its rectangle grown by the
  // region-growing reach; -1 for none.
  std::vector<std::int64_t> nearest_segments(const std::vector<std::uint32_t>& points, double max_distance) const;
  // Points with a segment within the inlier distance join it; the others,
  // when fresh, wait for a plane search.
  void attach_points(const std::vector<std::uint32_t>& points, Work& work, bool fresh);
  void repair(std::uint32_t id, Work& work);
  void search(ClassId label, Work& work);
  std::uint32_t create(ClassId label, const std::vector<std::uint32_t>& points);
  void absorb(std::uint32_t survivor, std::uint32_t absorbed);
  void merge_changed(Work& work);
  void refresh(std::uint32_t id);
  void compact_members(Record& record, std::uint32_t id);
  // Keeps the stored points flagged in `keep` and renumbers every list that
  // names points (members, pending lists, per-point scratch) and the scans'
  // origins to match.
  void compact_points(const std::vector<std::uint8_t>& keep);
  // A fresh stamp for marks_: points marked with it were seen in this pass.
  std::uint32_t next_mark();
  Eigen::Vector3d origin_of(std::uint32_t point) const;
  bool known_origin(std::uint32_t point) const;

  SegmentSettings settings_;
  LabelledVoxels voxels_;
  std::vector<Eigen::Vector3d> origins_;  // per integrated scan
  std::vector<std::uint64_t> queued_in_;  // per point: the call that last queued it
  std::uint64_t calls_ = 0;
  std::vector<std::uint32_t> marks_;  // per point, for de-duplicating lists
  std::uint32_t mark_ = 0;
  std::vector<Record> records_;           // indexed by segment id; dead ones stay
  std::vector<std::int64_t> merged_into_;  // per id: survivor, -1 alive, -2 dissolved
  std::vector<std::pair<std::uint32_t, std::uint32_t>> merges_;
  std::array<std::vector<std::uint32_t>, kClassCount> pending_;
  std::array<std::size_t, kClassCount> new_pending_{};  // joined since the class's last search
  std::array<std::uint64_t, kClassCount> searches_{};
};

}  // namespace sarmap::segments
