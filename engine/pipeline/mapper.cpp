#include "engine/pipeline/mapper.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <utility>

#include <tbb/parallel_for.h>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/core/prefetched_key_walk.hpp"
#include "engine/core/wake_workers.hpp"
#include "engine/geometry/triangle_scene.hpp"
#include "engine/metric/voxel_key.hpp"
#include "engine/pipeline/voxel_classes_from_point_map.hpp"

namespace sarmap::pipeline {

namespace {

metric::MetricMapSettings map_settings(const MapperConfig& c) {
  metric::MetricMapSettings s = c.map;
  s.resolution = c.voxel;
  return s;
}

// Adds each named count to a stage's counters.
void add_counts(StageProfile& profile, std::string_view stage,
                std::initializer_list<std::pair<std::string_view, double>> counts) {
  for (const auto& [name, value] : counts) profile.add_count(stage, name, value);
}

segments::SegmentSettings segment_settings(const MapperConfig& c, const SensorInfo& sensor) {
  segments::SegmentSettings s = c.segments;
  if (sensor.type == SensorType::Lidar) s.max_range = c.segment_max_range_lidar;
  return s;
}

metric::IntegratorSettings integrator_settings(const MapperConfig& c, const SensorInfo& sensor) {
  metric::IntegratorSettings s = c.integrator;
  s.max_range = c.max_range > 0 ? c.max_range : sensor.max_range;
  return s;
}

}  // namespace

Mapper::Mapper(const MapperConfig& config, const SensorInfo& sensor)
    : config_(config),
      sensor_(sensor),
      map_(map_settings(config)),
      integrator_(integrator_settings(config, sensor)),
      classifier_(make_point_classifier(config.classifier)),
      segments_(segment_settings(config, sensor)),
      topo_(config.topo) {
  if (!(config.max_point_distance >= 0) || !std::isfinite(config.max_point_distance)) {
    throw Error(ErrorCode::InvalidArgument, "max_point_distance must be a finite number >= 0");
  }
  if (!(config.semantic_points_voxel >= 0)) {
    throw Error(ErrorCode::InvalidArgument, "semantic_points_voxel must be >= 0");
  }
  metric::validate(config.bounds);
  semantic_points_.enable_labels();
}

void Mapper::begin_scan() {
  profile_.begin_scan();
  row_open_ = true;
}

Error Mapper::scan_error(const Scan& scan, const Error& e) {
  return Error(e.code(), "scan " + std::to_string(scan.index) + " (" + scan.source + "): " + e.what());
}

void Mapper::refuse_scans_if_merged() const {
  if (!merged_) return;
  throw Error(ErrorCode::InvalidArgument,
              "a merged Mapper takes no more scans (map them with another Mapper and merge that one in)");
}

void Mapper::integrate(Scan& scan) {
  refuse_scans_if_merged();
  if (!row_open_) profile_.begin_scan();
  row_open_ = false;
  try {
    run_stages(scan);
  } catch (const Error& e) {
    throw scan_error(scan, e);
  }
}

void Mapper::run_stages(Scan& scan) {
  std::vector<VoxelClassUpdate> voxel_classes;
  const std::uint64_t number = classify_half(scan, profile_, voxel_classes);
  maps_half(scan, number, profile_, voxel_classes);
}

std::uint64_t Mapper::classify_half(Scan& scan, StageProfile& profile, std::vector<VoxelClassUpdate>& voxel_classes) {
  const std::uint64_t number = ++classify_stages_;
  // The metric stage's parallel loops follow preprocess and classify (with
  // the labels as classes, about 0.1 ms together for a 320 x 240 scan): the
  // other threads, asleep since the last scan's stages, are woken now and
  // again before classify, so that they are awake when those loops start
  // whether the two stages take longer than the workers spin or not
  // (wake_workers.hpp).
  wake_workers();
  forget_in_classifier(number, profile);
  {
    const auto timer = profile.time("preprocess");
    const Eigen::Vector3d& o = scan.origin;
    if (!metric::within_map_limits(o.x(), o.y(), o.z()) || !scan.pose.matrix().allFinite()) {
      throw Error(ErrorCode::OutOfRange, "sensor origin (" + std::to_string(o.x()) + ", " + std::to_string(o.y()) +
                                             ", " + std::to_string(o.z()) +
                                             ") or pose is not finite or beyond the map limits of +-10 km");
    }
    profile.add_count("preprocess", "points_in", static_cast<double>(scan.points.size()));
    scan.points.remove_non_finite();
    if (config_.max_point_distance > 0) {
      const std::size_t far = scan.points.remove_farther_than(o, config_.max_point_distance);
      profile.add_count("preprocess", "points_far", static_cast<double>(far));
    }
    profile.add_count("preprocess", "points_out", static_cast<double>(scan.points.size()));
  }
  wake_workers();
  const auto timer = profile.time("classify");
  // The input's labels are ground truth (kept as gt_label unless the input
  // carries its own); any classifier but "labels" then overwrites label.
  if (scan.points.has_labels() && !scan.points.has_gt_labels()) {
    scan.points.enable_gt_labels();
    std::copy(scan.points.labels().begin(), scan.points.labels().end(), scan.points.gt_labels().begin());
  }
  const ClassifyCounts counts = classifier_->classify(scan.points);
  add_counts(profile, "classify",
             {{"points", scan.points.size()},
              {"blocks", counts.blocks},
              {"unlabelled", counts.unlabelled}});
  for (std::size_t r = 0; r < kRuleCount; ++r) {
    profile.add_count("classify", kRuleNames[r], static_cast<double>(counts.rules.changed[r]));
  }
  if (classifier_->labels_arrive_late()) {
    profile.add_count("classify", "map_points_added", static_cast<double>(counts.map_points_added));
  }
  // What the metric stage needs of the classifier, read now: the next scan's
  // classification may already run while this one's rays go in.
  if (const DgcnnMapClassifier* on_map = classifier_->accumulated_map()) {
    voxel_classes = voxel_classes_from_point_map(*on_map, map_.inv_resolution());
    profile.set_level("classify", "point_map_bytes", static_cast<double>(classifier_->memory_bytes()));
  }
  return number;
}

metric::IntegrationStats Mapper::trace_rays(const Scan& scan, std::size_t slot, StageProfile& profile) {
  const auto timer = profile.time("metric");
  return integrator_.trace(slot, map_.resolution(), scan.points, scan.origin);
}

void Mapper::maps_half(Scan& scan, std::uint64_t classify_number, StageProfile& profile,
                       const std::vector<VoxelClassUpdate>& voxel_classes,
                       std::optional<TracedRays> traced_rays) {
  if (!traced_rays) traced_rays = TracedRays{0, trace_rays(scan, 0, profile)};
  {
    const auto timer = profile.time("metric");
    metric::IntegrationStats& s = traced_rays->stats;
    integrator_.apply(map_, traced_rays->slot, s);
    stats_ += s;
    add_counts(profile, "metric",
               {{"points_in", s.points_in},
                {"points_rejected", s.points_rejected},
                {"rays", s.rays},
                {"voxel_visits", s.voxel_visits},
                {"voxels_updated", s.hits + s.misses}});
    if (classifier_->accumulated_map() != nullptr) {
      const std::size_t voxels = apply_voxel_classes(voxel_classes, map_, classes_changed_);
      profile.add_count("metric", "voxels_classed_from_point_map", static_cast<double>(voxels));
    }
    // Scans too large for the dense scratch run slower through hash tables (IntegratorSettings).
    profile.add_count("metric", "scans_hashed_walk", static_cast<double>(s.rays > 0 ? 1 - s.dense_walks : 0));
    if (config_.bounds.limited()) {
      const std::size_t dropped = metric::apply_bounds(map_, scan.origin, config_.bounds);
      blocks_dropped_ += dropped;
      blocks_dropped_unforgotten_ += dropped;
      profile.add_count("metric", "blocks_dropped", static_cast<double>(dropped));
    }
  }
  // Memory after the scan, outside the stage's time: the map as it counts
  // itself, and apart from it the integrator's scratch (docs/formats.md,
  // profile.json). The classifier's point map is measured in its own half.
  profile.set_level("metric", "map_bytes", static_cast<double>(map_.memory_bytes()));
  profile.set_level("metric", "integrator_scratch_bytes", static_cast<double>(integrator_.scratch_bytes()));
  if (forgetting_due()) forget_dropped_regions(classify_number, profile);
  {
    const auto timer = profile.time("segment");
    const segments::SegmentUpdate u = segments_.integrate(scan.points, scan.origin);
    add_counts(profile, "segment",
               {{"points_in", u.points_in},
                {"points_far", u.points_far},
                {"points_new", u.points_new},
                {"points_attached", u.points_attached},
                {"planes_found", u.planes_found},
                {"created", u.created},
                {"merged", u.merged},
                {"removed", u.removed}});
  }
  profile.set_level("segment", "bytes", static_cast<double>(segments_.memory_bytes()));
  {
    const auto timer = profile.time("topo");
    // The scan changed voxels only between its origin and its points.
    Bounds changed = scan.points.bounds();
    changed.extend(scan.origin);
    changed.extend(classes_changed_);
    classes_changed_ = {};
    const topo::TopoUpdate u = topo_.update(segments_, map_, &changed);
    add_counts(profile, "topo",
               {{"nodes_added", u.nodes_added},
                {"nodes_retired", u.nodes_retired},
                {"candidates", u.candidates},
                {"rejected_wall", u.rejected_wall},
                {"rejected_drop", u.rejected_drop},
                {"rejected_steep", u.rejected_steep},
                {"rejected_unknown", u.rejected_unknown}});
  }
  // Embree's part apart: its device serves every scene of the process.
  profile.set_level("topo", "bytes", static_cast<double>(topo_.memory_bytes()));
  profile.set_level("topo", "embree_bytes", static_cast<double>(geometry::embree_bytes()));
  {
    const auto timer = profile.time("semantic_points");
    profile.add_count("semantic_points", "points_kept", static_cast<double>(keep_semantic_points(scan.points)));
  }
  profile.set_level("semantic_points", "bytes", static_cast<double>(semantic_points_bytes()));
}

void Mapper::finish() {
  if (merged_) return;  // both sides were finished before they merged
  forget_in_classifier(std::numeric_limits<std::uint64_t>::max(), profile_);
  if (classifier_->accumulated_map() == nullptr) return;
  Bounds changed;
  {
    const auto timer = profile_.time("classify");
    profile_.add_count("classify", "blocks_at_finish", static_cast<double>(classifier_->finish()));
  }
  {
    const auto timer = profile_.time("metric");
    const std::size_t voxels = apply_voxel_classes(
        voxel_classes_from_point_map(*classifier_->accumulated_map(), map_.inv_resolution()), map_,
        changed);
    profile_.add_count("metric", "voxels_classed_from_point_map", static_cast<double>(voxels));
  }
  if (changed.empty()) return;
  // The topological map follows the classes the last blocks gave.
  const auto timer = profile_.time("topo");
  topo_.update(segments_, map_, &changed);
}

bool Mapper::forgetting_due() const {
  return blocks_dropped_unforgotten_ > 0 && blocks_dropped_unforgotten_ * 8 >= map_.blocks().block_count();
}

bool Mapper::in_kept_block(double x, double y, double z) const {
  return metric::within_map_limits(x, y, z) &&
         map_.blocks().find(metric::block_of(metric::key_of(x, y, z, map_.inv_resolution()))) != nullptr;
}

void Mapper::forget_dropped_regions() {
  // Idle between scans: every part of the pass now, the pending ones first.
  forget_in_classifier(std::numeric_limits<std::uint64_t>::max(), profile_);
  forget_dropped_regions(classify_stages_, profile_);
  forget_in_classifier(std::numeric_limits<std::uint64_t>::max(), profile_);
}

void Mapper::forget_in_classifier(std::uint64_t classify_number, StageProfile& profile) {
  std::vector<ClassifierForget> due;
  {
    const std::lock_guard<std::mutex> lock(classifier_forgets_mutex_);
    auto it = classifier_forgets_.begin();
    while (it != classifier_forgets_.end() && it->at_classify <= classify_number) ++it;
    due.assign(std::make_move_iterator(classifier_forgets_.begin()), std::make_move_iterator(it));
    classifier_forgets_.erase(classifier_forgets_.begin(), it);
  }
  for (const ClassifierForget& pass : due) {
    // Only a scan read too early (more than two in flight) lets a pass miss its turn.
    if (classify_number != std::numeric_limits<std::uint64_t>::max() && pass.at_classify != classify_number) {
      throw std::logic_error("Mapper: a forgetting pass reached the classifier after its classify stage");
    }
    const auto timer = profile.time("classify");
    const double inv = map_.inv_resolution();
    const std::size_t points = classifier_->forget([&](double x, double y, double z) {
      if (!metric::within_map_limits(x, y, z)) return true;
      const std::uint64_t block = metric::pack(metric::block_of(metric::key_of(x, y, z, inv)));
      return !std::binary_search(pass.kept_blocks.begin(), pass.kept_blocks.end(), block);
    });
    profile.add_count("classify", "map_points_forgotten", static_cast<double>(points));
  }
}

void Mapper::forget_dropped_regions(std::uint64_t classify_number, StageProfile& profile) {
  blocks_dropped_unforgotten_ = 0;
  {
    const auto timer = profile.time("segment");
    const segments::SegmentUpdate u =
        segments_.forget([&](const Eigen::Vector3d& p) { return !in_kept_block(p.x(), p.y(), p.z()); });
    add_counts(profile, "segment", {{"points_forgotten", u.points_forgotten}, {"removed", u.removed}});
  }
  {
    ClassifierForget pass;
    pass.at_classify = classify_number + kClassifierForgetLag;
    pass.kept_blocks.reserve(map_.blocks().block_count());
    map_.blocks().for_each_block(
        [&](const metric::BlockKey& key, const auto&) { pass.kept_blocks.push_back(metric::pack(key)); });
    std::sort(pass.kept_blocks.begin(), pass.kept_blocks.end());
    const std::lock_guard<std::mutex> lock(classifier_forgets_mutex_);
    classifier_forgets_.push_back(std::move(pass));
  }
  std::vector<std::uint32_t> keep;
  keep.reserve(semantic_points_.size());
  for (std::uint32_t i = 0; i < semantic_points_.size(); ++i) {
    if (in_kept_block(semantic_points_.x()[i], semantic_points_.y()[i], semantic_points_.z()[i])) keep.push_back(i);
  }
  const std::size_t forgotten = semantic_points_.size() - keep.size();
  profile.add_count("metric", "semantic_points_forgotten", static_cast<double>(forgotten));
  if (forgotten == 0) return;
  semantic_points_ = semantic_points_.select(keep);
  semantic_keys_ = FlatKeySet(keep.size());
  for (std::size_t i = 0; i < semantic_points_.size(); ++i) semantic_keys_.insert(semantic_key(i));
}

std::uint64_t Mapper::semantic_key(std::size_t i) const {
  // As keep_semantic_points keyed the point: its float coordinates, widened.
  const double x = semantic_points_.x()[i], y = semantic_points_.y()[i], z = semantic_points_.z()[i];
  return metric::pack(metric::key_of(x, y, z, 1.0 / config_.semantic_points_voxel));
}

std::size_t Mapper::keep_semantic_points(const PointBuffer& points) {
  if (config_.semantic_points_voxel <= 0) return 0;
  const double inv = 1.0 / config_.semantic_points_voxel;
  // Where labels arrive late, a voxel keeps its first classified point: an
  // unknown one now would hide the class a later scan brings.
  const bool skip_unknown = classifier_->labels_arrive_late() && points.has_labels();
  const auto voxel_key = [&](std::size_t i, std::uint64_t& key) {
    const double x = points.x()[i], y = points.y()[i], z = points.z()[i];
    if (!metric::within_map_limits(x, y, z)) return false;
    if (skip_unknown && points.labels()[i] == static_cast<std::uint8_t>(ClassId::Unknown)) return false;
    key = metric::pack(metric::key_of(x, y, z, inv));
    return true;
  };
  // Most points fall in voxels that earlier scans' points hold. Those are
  // found first, in parallel and leaving the index as it is; then, in input
  // order, each remaining point is kept when it is the first in its voxel:
  // the points one pass in order would keep, on any number of threads.
  constexpr std::size_t kChunk = 4096;
  const std::size_t chunks = (points.size() + kChunk - 1) / kChunk;
  std::vector<std::vector<std::pair<std::uint32_t, std::uint64_t>>> unseen(chunks);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    // A repeat (the point before in the same voxel) is in an indexed voxel,
    // or in a new one whose first point that one is: never kept.
    const auto note_unseen = [&unseen, c, this](std::size_t i, std::uint64_t key, bool repeat) {
      if (!repeat && !semantic_keys_.contains(key)) {
        unseen[c].emplace_back(static_cast<std::uint32_t>(i), key);
      }
    };
    walk_keys_prefetched(semantic_keys_, c * kChunk, std::min(points.size(), (c + 1) * kChunk), voxel_key,
                         note_unseen);
  });
  std::vector<std::uint32_t> keep;
  for (const auto& chunk : unseen) {
    for (const auto& [i, key] : chunk) {
      if (semantic_keys_.insert(key)) keep.push_back(i);
    }
  }
  // Only what semantic_points.ply carries: position, prediction, scores, truth.
  PointBuffer kept = points.select(keep);
  PointBuffer slim;
  slim.enable_labels();
  if (kept.has_gt_labels()) slim.enable_gt_labels();
  slim.resize(kept.size());
  std::copy(kept.x().begin(), kept.x().end(), slim.x().begin());
  std::copy(kept.y().begin(), kept.y().end(), slim.y().begin());
  std::copy(kept.z().begin(), kept.z().end(), slim.z().begin());
  if (kept.has_labels()) std::copy(kept.labels().begin(), kept.labels().end(), slim.labels().begin());
  if (kept.has_gt_labels()) std::copy(kept.gt_labels().begin(), kept.gt_labels().end(), slim.gt_labels().begin());
  for (std::size_t c = 0; c < kept.score_count(); ++c) {
    const std::size_t channel = slim.add_score(kept.score_names()[c]);
    std::copy(kept.score(c).begin(), kept.score(c).end(), slim.score(channel).begin());
  }
  semantic_points_.append(slim);
  return keep.size();
}

}  // namespace sarmap::pipeline
