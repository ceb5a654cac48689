// The pipeline: the only place that knows every stage. A Mapper owns the maps
// and runs the stages on each scan in order (preprocess, classify, metric,
// segment, topo), timing each into a StageProfile. Fed a stream of scans, it
// classifies the next scan while the maps take the one before
// (integrate_stream), with the same maps as one scan at a time.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/flat_key_set.hpp"
#include "engine/core/point_buffer.hpp"
#include "engine/core/scan.hpp"
#include "engine/core/sensor_info.hpp"
#include "engine/core/stage_profile.hpp"
#include "engine/metric/map_bounds.hpp"
#include "engine/metric/map_merge.hpp"
#include "engine/metric/metric_map.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "engine/pipeline/point_classifier.hpp"
#include "engine/pipeline/voxel_classes_from_point_map.hpp"
#include "engine/segments/segment_map.hpp"
#include "engine/topo/topo_map.hpp"

namespace sarmap::pipeline {

struct MapperConfig {
  double voxel = 0.05;  // metric map resolution, metres
  // Rays longer than this are cut (misses only); 0 takes the sequence's
  // sensor.max_range, and no limit when that is 0 too.
  double max_range = 0.0;
  // Points farther than this from their scan's origin are dropped and counted
  // (preprocess points_far): a stray far outlier would otherwise stretch every
  // stage's grids over kilometres. 0 keeps all.
  double max_point_distance = 1000.0;
  // Where point classes come from: the DGCNN (default), the geometric
  // baseline, or the input's label property.
  ClassifierConfig classifier;
  metric::MetricMapSettings map;  // its resolution is replaced by `voxel`
  metric::IntegratorSettings integrator;  // its max_range is replaced as above
  // Keep the map bounded around the sensor (radius, block budget); unlimited
  // by default. What the metric map drops, the segment stage's points and
  // the kept semantic points let go of too, once the blocks dropped since
  // they last did reach an eighth of the map's blocks (so the work is spread
  // thin): a bounded run's memory stays flat, and its segments, graph and
  // points describe the region around the sensor, not the whole mission.
  metric::MapBounds bounds;
  // Keep one classified point per voxel of this size for semantic_points.ply (0 keeps none).
  double semantic_points_voxel = 0.05;
  // Planar segments of the classified points (segment stage). Its max_range
  // (3 m) suits depth cameras, whose noise grows with the square of the range;
  // for a LiDAR the stage uses segment_max_range_lidar instead (0: no limit).
  segments::SegmentSettings segments;
  double segment_max_range_lidar = 0.0;
  // The topological map and its planners (topo stage).
  topo::TopoSettings topo;
};

// A scan's rays traced ahead of its metric stage (RayIntegrator::trace): the
// integrator's slot that holds them and their figures so far.
struct TracedRays {
  std::size_t slot = 0;
  metric::IntegrationStats stats;
};

// One scan of a stream (Mapper::integrate_stream), as it reaches the caller
// again: mapped, or with the error that cost it.
struct StreamedScan {
  std::size_t frame = 0;  // its position in the input
  Scan scan;
  bool mapped = false;
  bool read_failed = false;    // the reader threw: `scan` holds nothing
  std::optional<Error> error;  // why it was not mapped
  // Set by the Mapper: the scan's stage times, and its classify stage's
  // hand-over to the metric stage.
  StageProfile profile;
  std::vector<VoxelClassUpdate> voxel_classes;
  std::uint64_t classify_number = 0;
  double read_start_s = 0;  // steady clock, for its latency
  // With stages overlapping: its rays, traced while the scan before was being mapped.
  std::optional<TracedRays> traced_rays;
};

// What Mapper::merge did, by map.
struct MapperMergeCounts {
  metric::MergeCounts metric;
  std::size_t semantic_points_added = 0;  // kept points in voxels only the other Mapper held
  segments::SegmentUpdate segments;
  topo::TopoUpdate topo;
};

// Whether a stream's stages overlap: never changes the maps, only the time.
enum class StageOverlap { Off, On };

class Mapper {
 public:
  // Throws sarmap::Error: InvalidArgument for an unknown classifier or bad
  // settings, the model loader's errors for a bad model file.
  Mapper(const MapperConfig& config, const SensorInfo& sensor = {});

  // Opens the profile row of the next scan, so a caller can time its own
  // stages (reading) into it; integrate() opens one itself otherwise.
  void begin_scan();
  // Runs every stage on one scan (its points are filtered in place). Throws
  // sarmap::Error naming the scan (index and source) for a scan it refuses: an
  // origin or pose that is not finite or lies beyond the map's limits, or
  // points a stage cannot take. Those checks come before any map changes, so
  // a caller may skip the scan and go on (`sarmap run` does, unless --strict).
  void integrate(Scan& scan);

  // Reads scans with `read` (frame numbers from `first_frame` on) until it
  // returns false, maps each as integrate() would and hands it to `done` in
  // input order, mapped or not: a reader's sarmap::Error costs that frame, a
  // scan the Mapper refuses costs that scan. `done` may throw to end the
  // stream (no later scan reaches the maps, but the next one may have been
  // classified: like a stage's error inside integrate(), such a Mapper is
  // not to be continued). With StageOverlap::On the classify stage of one
  // scan and the tracing of its rays (the metric stage's first half) run
  // while the metric stage's update, segment and topo stages take the one
  // before (a oneTBB pipeline of four serial filters: read, classify, trace,
  // maps); the maps, the classifier's state and the profile's counters are those of
  // StageOverlap::Off. Between calls the Mapper is idle, so a caller reads or saves it there
  // (`sarmap run`'s snapshots and checkpoints end one call and start the next).
  using ScanReader = std::function<bool(std::size_t frame, Scan& scan)>;
  using ScanDone = std::function<void(StreamedScan& scan)>;
  void integrate_stream(std::size_t first_frame, const ScanReader& read, const ScanDone& done,
                        StageOverlap overlap = StageOverlap::On);

  // The scans have ended: where classes come from the accumulated map, the
  // blocks still waiting for more points are classified and the metric map's
  // voxels take their classes (profile: classify.blocks_at_finish). Call it
  // before reading the final maps; the segments and the topological map keep
  // the classes their scans had. Scans may still follow.
  void finish();

  // Merges `other`'s maps into this Mapper's (another robot's run in the
  // same map frame, or another part of the sequence): finishes both, then
  // the metric map merges voxel by voxel (metric::merge_into), the kept
  // semantic points by voxel (a voxel this Mapper holds keeps its point),
  // the classifier of the accumulated map's labelled point map by cell (the
  // kept points and voxels take their classes from it), the segments by the
  // scan-by-scan merge rule (SegmentMap::merge), and the topological map is
  // rebuilt from the merged segments and map; the profile takes `other`'s
  // scans. `other` keeps its maps. A merged Mapper is a finished map: it
  // takes no more scans (integrate and integrate_stream throw) and finish()
  // does nothing, since the classifier's block schedule and ramp-deck memory
  // hold one side only; it may take further merges, and
  // its state saves and loads (save_state) as a merged Mapper's, so merges
  // can reduce on other processes. Throws sarmap::Error (InvalidArgument) naming both values when
  // the metric map settings, the segment or kept-point voxel, or the
  // classifier differ, or for a Mapper merged into itself; nothing is
  // changed then. `other_to_this` carries `other`'s map frame into this
  // one's (robots whose frames differ by a known transform): the kept points
  // and the segments' stored points and scan origins move exactly, the
  // metric map is resampled (metric::transformed_map: exact for whole-voxel
  // shifts and quarter turns of yaw).
  MapperMergeCounts merge(Mapper& other, const Pose& other_to_this = {});
  bool merged() const { return merged_; }

  const MapperConfig& config() const { return config_; }
  // The sensor it was made for (its range and kind shape the integrator and
  // the segment stage): with config(), what a Mapper that loads this one's
  // state must be made with.
  const SensorInfo& sensor() const { return sensor_; }
  double max_range() const { return integrator_.settings().max_range; }
  const metric::MetricMap& metric_map() const { return map_; }
  const metric::IntegrationStats& metric_stats() const { return stats_; }
  // Blocks dropped so far by the map bounds.
  std::size_t blocks_dropped() const { return blocks_dropped_; }
  const PointClassifier& classifier() const { return *classifier_; }
  const segments::SegmentMap& segment_map() const { return segments_; }
  const topo::TopoMap& topo_map() const { return topo_; }
  // Classified points kept so far: label = prediction, its per-class scores
  // when the classifier gives them, gt_label = the input's label when it had one.
  const PointBuffer& semantic_points() const { return semantic_points_; }
  // Bytes the kept points take: their arrays and the index of their voxels,
  // by capacity. Map state beside the metric map, which does not count it.
  std::size_t semantic_points_bytes() const { return semantic_points_.memory_bytes() + semantic_keys_.memory_bytes(); }
  StageProfile& profile() { return profile_; }
  const StageProfile& profile() const { return profile_; }

  // Lets the segment map and the kept semantic points go of every point whose
  // metric block the map no longer holds (or never held), counted in the
  // profile (segment.points_forgotten, metric.semantic_points_forgotten).
  // integrate() calls it itself as the bounds drop blocks; a caller may call
  // it before reading the maps so that they cover the same region exactly
  // (the topological map follows at the next scan).
  void forget_dropped_regions();

  // Every stage's state between scans (maps, classifier memory, segments,
  // topological map, kept points, profile), for a checkpoint
  // (engine/pipeline/checkpoint.hpp): a Mapper with the same config that
  // loads it continues exactly as this one would, bit for bit.
  void save_state(StateWriter& out) const;
  // Throws sarmap::Error (Parse) naming the offset for a stream this config
  // cannot continue (another classifier, voxel size, a damaged stream). The
  // Mapper may be half-loaded after a throw: make a new one to go on.
  void load_state(StateReader& in);

 private:
  void run_stages(Scan& scan);
  // The two halves of run_stages, each timed into `profile`: preprocess and
  // classify (the classifier's state only; returns the scan's number among
  // the classify stages run), then the maps' stages.
  std::uint64_t classify_half(Scan& scan, StageProfile& profile, std::vector<VoxelClassUpdate>& voxel_classes);
  // `traced_rays` are the scan's rays if trace_rays() found them already;
  // otherwise the metric stage traces them itself (in the integrator's slot 0).
  void maps_half(Scan& scan, std::uint64_t classify_number, StageProfile& profile,
                 const std::vector<VoxelClassUpdate>& voxel_classes,
                 std::optional<TracedRays> traced_rays = {});
  // The metric stage's first half, timed as "metric": the scan's rays into
  // the integrator's `slot`. It reads nothing of the maps, so a stream runs
  // it while the scan before is being mapped.
  metric::IntegrationStats trace_rays(const Scan& scan, std::size_t slot, StageProfile& profile);
  // The classifier's share of the forgetting passes due by `classify_number`.
  void forget_in_classifier(std::uint64_t classify_number, StageProfile& profile);
  void stream_in_order(std::size_t first_frame, const ScanReader& read, const ScanDone& done);
  void stream_overlapped(std::size_t first_frame, const ScanReader& read, const ScanDone& done);
  // Throws for a merged Mapper (merge()).
  void refuse_scans_if_merged() const;
  // integrate()'s error naming the scan.
  static Error scan_error(const Scan& scan, const Error& e);
  // Keeps each point that is the first in its voxel (semantic_points_voxel);
  // returns how many it kept.
  std::size_t keep_semantic_points(const PointBuffer& points);
  // The voxel key of kept point i.
  std::uint64_t semantic_key(std::size_t i) const;
  // Whether the blocks dropped since the last forget_dropped_regions() call
  // are enough to make it worth one.
  bool forgetting_due() const;
  bool in_kept_block(double x, double y, double z) const;
  // A pass from the maps' stages of scan `classify_number`; the classifier's
  // share waits for the second classify stage after it (kClassifierForgetLag).
  void forget_dropped_regions(std::uint64_t classify_number, StageProfile& profile);

  MapperConfig config_;
  SensorInfo sensor_;
  metric::MetricMap map_;
  metric::RayIntegrator integrator_;
  metric::IntegrationStats stats_;
  std::size_t blocks_dropped_ = 0;
  std::size_t blocks_dropped_unforgotten_ = 0;  // since the last forget_dropped_regions()
  std::unique_ptr<PointClassifier> classifier_;
  segments::SegmentMap segments_;
  topo::TopoMap topo_;
  StageProfile profile_;
  PointBuffer semantic_points_;
  bool row_open_ = false;
  bool merged_ = false;  // merge() made this Mapper: no more scans
  // A forgetting pass reaches the classifier at the start of the second
  // classify stage after the scan whose maps' stages made it, with the blocks
  // the metric map held then: with stages overlapping, the next scan's
  // classification may already run while the pass is made, never the one
  // after (integrate_stream keeps two scans in flight). In order, the same.
  static constexpr std::uint64_t kClassifierForgetLag = 2;
  struct ClassifierForget {
    std::uint64_t at_classify = 0;           // the classify stage (counted from 1) that applies it
    std::vector<std::uint64_t> kept_blocks;  // packed metric block keys, sorted
  };
  std::uint64_t classify_stages_ = 0;
  std::vector<ClassifierForget> classifier_forgets_;  // by at_classify
  std::mutex classifier_forgets_mutex_;               // the maps' stages add while a classify stage takes
  Bounds classes_changed_;  // voxels the classifier of the accumulated map relabelled, for the next topo update
  // The voxels holding a kept point (semantic_key of each).
  FlatKeySet semantic_keys_;
};

}  // namespace sarmap::pipeline
