#include "engine/pipeline/mapper.hpp"

#include <algorithm>

#include "engine/core/error.hpp"
#include "engine/metric/voxel_key.hpp"

namespace sarmap::pipeline {

namespace {

metric::MetricMapSettings map_settings(const MapperConfig& c) {
  metric::MetricMapSettings s = c.map;
  s.resolution = c.voxel;
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
      map_(map_settings(config)),
      integrator_(integrator_settings(config, sensor)),
      classifier_(make_point_classifier(config.classifier)),
      segments_(config.segments),
      topo_(config.topo) {
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

void Mapper::integrate(Scan& scan) {
  if (!row_open_) profile_.begin_scan();
  row_open_ = false;
  {
    const auto timer = profile_.time("preprocess");
    profile_.add_count("preprocess", "points_in", static_cast<double>(scan.points.size()));
    scan.points.remove_non_finite();
    profile_.add_count("preprocess", "points_out", static_cast<double>(scan.points.size()));
  }
  {
    const auto timer = profile_.time("classify");
    // The input's labels are ground truth (kept as gt_label unless the input
    // carries its own); any classifier but "labels" then overwrites label.
    if (scan.points.has_labels() && !scan.points.has_gt_labels()) {
      scan.points.enable_gt_labels();
      std::copy(scan.points.labels().begin(), scan.points.labels().end(), scan.points.gt_labels().begin());
    }
    try {
      const ClassifyCounts counts = classifier_->classify(scan.points);
      profile_.add_count("classify", "points", static_cast<double>(scan.points.size()));
      profile_.add_count("classify", "blocks", static_cast<double>(counts.blocks));
      profile_.add_count("classify", "unlabelled", static_cast<double>(counts.unlabelled));
      profile_.add_count("classify", "ramp_vetoed", static_cast<double>(counts.vetoed));
      profile_.add_count("classify", "wall_bands", static_cast<double>(counts.wall_bands));
      profile_.add_count("classify", "ramp_sides", static_cast<double>(counts.ramp_sides));
      profile_.add_count("classify", "wall_feet", static_cast<double>(counts.wall_feet));
    } catch (const Error& e) {
      throw Error(e.code(), "scan " + std::to_string(scan.index) + " (" + scan.source + "): " + e.what());
    }
  }
  {
    const auto timer = profile_.time("metric");
    const metric::IntegrationStats s = integrator_.integrate(map_, scan.points, scan.origin);
    stats_ += s;
    profile_.add_count("metric", "points_in", static_cast<double>(s.points_in));
    profile_.add_count("metric", "points_rejected", static_cast<double>(s.points_rejected));
    profile_.add_count("metric", "rays", static_cast<double>(s.rays));
    profile_.add_count("metric", "voxel_visits", static_cast<double>(s.voxel_visits));
    profile_.add_count("metric", "voxels_updated", static_cast<double>(s.hits + s.misses));
    // Scans too large for the dense scratch run slower through hash tables (IntegratorSettings).
    profile_.add_count("metric", "scans_hashed_walk", static_cast<double>(s.rays > 0 ? 1 - s.dense_walks : 0));
    if (config_.bounds.limited()) {
      const std::size_t dropped = metric::apply_bounds(map_, scan.origin, config_.bounds);
      blocks_dropped_ += dropped;
      profile_.add_count("metric", "blocks_dropped", static_cast<double>(dropped));
    }
  }
  {
    const auto timer = profile_.time("segment");
    const segments::SegmentUpdate u = segments_.integrate(scan.points, scan.origin);
    profile_.add_count("segment", "points_in", static_cast<double>(u.points_in));
    profile_.add_count("segment", "points_far", static_cast<double>(u.points_far));
    profile_.add_count("segment", "points_new", static_cast<double>(u.points_new));
    profile_.add_count("segment", "points_attached", static_cast<double>(u.points_attached));
    profile_.add_count("segment", "planes_found", static_cast<double>(u.planes_found));
    profile_.add_count("segment", "created", static_cast<double>(u.created));
    profile_.add_count("segment", "merged", static_cast<double>(u.merged));
    profile_.add_count("segment", "removed", static_cast<double>(u.removed));
  }
  {
    const auto timer = profile_.time("topo");
    const topo::TopoUpdate u = topo_.update(segments_, map_);
    profile_.add_count("topo", "nodes_added", static_cast<double>(u.nodes_added));
    profile_.add_count("topo", "nodes_retired", static_cast<double>(u.nodes_retired));
    profile_.add_count("topo", "candidates", static_cast<double>(u.candidates));
    profile_.add_count("topo", "rejected_wall", static_cast<double>(u.rejected_wall));
    profile_.add_count("topo", "rejected_drop", static_cast<double>(u.rejected_drop));
    profile_.add_count("topo", "rejected_steep", static_cast<double>(u.rejected_steep));
    profile_.add_count("topo", "rejected_unknown", static_cast<double>(u.rejected_unknown));
  }
  keep_semantic_points(scan.points);
}

void Mapper::keep_semantic_points(const PointBuffer& points) {
  if (config_.semantic_points_voxel <= 0) return;
  const double inv = 1.0 / config_.semantic_points_voxel;
  std::vector<std::uint32_t> keep;
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    const double x = points.x()[i], y = points.y()[i], z = points.z()[i];
    if (!metric::within_map_limits(x, y, z)) continue;
    const std::uint64_t key = metric::pack(metric::key_of(x, y, z, inv));
    if (semantic_keys_.insert(key).second) keep.push_back(i);
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
}

}  // namespace sarmap::pipeline
