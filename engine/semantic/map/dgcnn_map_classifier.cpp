// Blocks run in parallel, each reading only the map; their scores are then
// fused serially in block order, so the result is thread-count independent.
#include "engine/semantic/map/dgcnn_map_classifier.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/semantic/dgcnn/block_features.hpp"
#include "engine/semantic/dgcnn/block_sampling.hpp"
#include "engine/semantic/dgcnn/dgcnn_classifier.hpp"
#include "engine/semantic/dgcnn/score_carry_back.hpp"

namespace sarmap {

namespace {

MapBlockSettings block_settings(const DgcnnModel& model, const DgcnnMapClassifierSettings& s) {
  MapBlockSettings b;
  b.block_size = model.metadata().block_size;
  b.stride = s.stride > 0.0 ? s.stride : kDefaultStrideFraction * b.block_size;
  b.min_points = s.min_points;
  b.growth = s.growth;
  b.min_new_points = s.min_new_points;
  return b;
}

// A seed per block and classification, so that a block classified again
// draws other samples and no two blocks share theirs.
std::uint64_t block_stream(const MapBlock& block) {
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (const std::uint64_t v : {static_cast<std::uint64_t>(block.i), static_cast<std::uint64_t>(block.j),
                                static_cast<std::uint64_t>(block.classifications)}) {
    h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  }
  return h;
}

}  // namespace

DgcnnMapClassifier::DgcnnMapClassifier(const DgcnnModel& model, const DgcnnMapClassifierSettings& settings)
    : model_(require_labelling_metadata(model)),
      settings_(settings),
      class_probabilities_(model.metadata().classes),
      map_(settings.cell, model.classes()),
      schedule_(block_settings(model, settings)) {}

std::vector<std::uint8_t> DgcnnMapClassifier::classify_block(const MapBlock& mb, DgcnnWorkspace& workspace) const {
  const DgcnnMetadata& m = model_.metadata();
  const std::size_t classes = model_.classes();
  const PointBuffer& points = map_.points();
  Block block;
  block.origin_x = static_cast<double>(mb.i) * schedule_.settings().stride;
  block.origin_y = static_cast<double>(mb.j) * schedule_.settings().stride;
  block.size = schedule_.settings().block_size;
  block.points = mb.points;
  const std::vector<std::uint32_t> samples =
      sample_block(block.points.size(), m.points_per_block, settings_.seed, block_stream(mb));
  std::vector<std::uint32_t> indices(samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) indices[k] = block.points[samples[k]];
  const BlockFrame frame{block.origin_x, block.origin_y, block.size, m.z_min, m.z_max};
  const std::vector<float> features = block_features(points, indices, frame, model_.channels() == 9);
  std::vector<float> logits(indices.size() * classes);
  model_.forward(features.data(), indices.size(), logits.data(), workspace);
  // Softmax per sample, quantised to the map's score scale.
  std::vector<std::uint8_t> sample_scores(indices.size() * classes);
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const float* row = logits.data() + k * classes;
    const float top = *std::max_element(row, row + classes);
    double sum = 0.0;
    std::vector<double> e(classes);
    for (std::size_t c = 0; c < classes; ++c) sum += (e[c] = std::exp(static_cast<double>(row[c] - top)));
    for (std::size_t c = 0; c < classes; ++c) {
      sample_scores[k * classes + c] = static_cast<std::uint8_t>(std::lround(e[c] / sum * kScoreScale));
    }
  }
  // Every block point takes its own sample's scores or its nearest sample's.
  const std::vector<std::uint32_t> nearest = nearest_sample(points, block, samples);
  std::vector<std::uint8_t> scores(block.points.size() * classes);
  for (std::size_t k = 0; k < block.points.size(); ++k) {
    std::copy_n(sample_scores.data() + static_cast<std::size_t>(nearest[k]) * classes, classes,
                scores.data() + k * classes);
  }
  return scores;
}

DgcnnMapClassifyStats DgcnnMapClassifier::classify(PointBuffer& scan) {
  if (model_.channels() == 9 && !scan.has_colors()) {
    throw Error(ErrorCode::InvalidArgument, "the DGCNN model takes colours (9 channels) but the cloud has none");
  }
  DgcnnMapClassifyStats stats;
  std::vector<std::uint32_t> added;
  const std::vector<std::uint32_t> of_point = map_.insert(scan, added);
  stats.map_points_added = added.size();
  schedule_.add_points(map_.points(), added);
  changed_ = added;

  const std::size_t waited_before = delays_.waiting();
  delays_.added(added, ++scans_);
  std::vector<MapBlock*> ready = schedule_.ready();
  add_blocks_of_long_waiting_points(ready);
  stats.blocks = classify_blocks(ready);
  settle_class_delays(stats.blocks > 0 ? 0 : waited_before);
  stats.unlabelled = label_points(scan, of_point);
  return stats;
}

void DgcnnMapClassifier::add_blocks_of_long_waiting_points(std::vector<MapBlock*>& ready) {
  const std::size_t wait = settings_.max_wait_scans;
  if (wait == 0 || scans_ <= wait) return;
  // A point waits only while no block holding it was classified after it
  // arrived and no neighbour a cell away has a class, so the points that
  // reach the wait now are all that can need a block for it.
  const std::size_t before = ready.size();
  const PointBuffer& points = map_.points();
  for (const std::uint32_t p : delays_.waiting_added_by(scans_ - static_cast<std::uint32_t>(wait))) {
    if (MapBlock* block = schedule_.most_central_unfinished(points.x()[p], points.y()[p])) ready.push_back(block);
  }
  if (ready.size() == before) return;
  const auto by_key = [](const MapBlock* a, const MapBlock* b) { return std::pair(a->j, a->i) < std::pair(b->j, b->i); };
  std::sort(ready.begin(), ready.end(), by_key);
  ready.erase(std::unique(ready.begin(), ready.end()), ready.end());
}

std::size_t DgcnnMapClassifier::classify_blocks(const std::vector<MapBlock*>& ready) {
  std::vector<std::vector<std::uint8_t>> scores(ready.size());
  tbb::parallel_for(std::size_t{0}, ready.size(), [&](std::size_t b) {
    DgcnnWorkspacePool::Loan workspace = workspaces_.borrow();
    scores[b] = classify_block(*ready[b], workspace.get());
  });
  for (std::size_t b = 0; b < ready.size(); ++b) {
    MapBlock& block = *ready[b];
    map_.fuse(std::span(block.points).first(block.classified_points), block.scores, -1);
    map_.fuse(block.points, scores[b], +1);
    changed_.insert(changed_.end(), block.points.begin(), block.points.end());
    block.scores = std::move(scores[b]);
    block.classified_points = block.points.size();
    ++block.classifications;
  }
  blocks_classified_ += ready.size();
  return ready.size();
}

std::size_t DgcnnMapClassifier::finish() {
  changed_.clear();
  const std::size_t blocks = classify_blocks(schedule_.unfinished());
  // What the last blocks give counts as arriving after the last scan.
  settle_class_delays();
  return blocks;
}

void DgcnnMapClassifier::settle_class_delays(std::size_t from) {
  delays_.settle(scans_, [&](std::uint32_t p) { return map_point_class(p) != ClassId::Unknown; }, from);
}

ClassId DgcnnMapClassifier::map_point_class(std::uint32_t p) const {
  const std::uint32_t scored = p == LabelledPointMap::kNoPoint ? p : map_.scored_point(p);
  if (scored == LabelledPointMap::kNoPoint || map_.hits(scored) == 0) return ClassId::Unknown;
  std::uint32_t per_class[kClassCount];
  class_probabilities_.sum(map_.score_sums(scored).data(), per_class);
  return class_probabilities_.classes()[class_probabilities_.best(per_class)];
}

std::size_t DgcnnMapClassifier::label_points(PointBuffer& points,
                                             std::span<const std::uint32_t> map_points) const {
  const std::size_t classes = model_.classes();
  const std::vector<ClassId>& out_classes = class_probabilities_.classes();
  points.enable_labels();
  std::vector<std::size_t> channel_of(out_classes.size());
  for (std::size_t c = 0; c < out_classes.size(); ++c) {
    const std::string name(class_info(out_classes[c]).name);
    const std::size_t existing = points.find_score(name);
    channel_of[c] = existing < points.score_count() ? existing : points.add_score(name);
  }
  std::vector<std::span<float>> channels;  // after every add_score
  for (const std::size_t channel : channel_of) channels.push_back(points.score(channel));
  const std::span<std::uint8_t> labels = points.labels();
  // In parallel over the points (each reads the map and writes only its
  // own label and scores): a depth camera's scan has tens of thousands,
  // and this ran on one core while the other waited for it.
  std::atomic<std::size_t> unknown{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<float> mean(classes), per_class(out_classes.size());
    std::size_t unknown_here = 0;
    // Neighbouring scan points (a depth image's row) mostly fall in one map
    // cell: the previous point's result is reused for the same map point.
    std::uint32_t previous = LabelledPointMap::kNoPoint;
    ClassId label = ClassId::Unknown;
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      if (i == r.begin() || map_points[i] != previous) {
        previous = map_points[i];
        // A point its block has not classified yet borrows the class of a
        // classified neighbour a cell away, if it has one: the block will
        // classify it when it has grown enough.
        const std::uint32_t p = previous == LabelledPointMap::kNoPoint ? previous : map_.scored_point(previous);
        label = map_point_class(p);
        if (label == ClassId::Unknown) {
          std::fill(per_class.begin(), per_class.end(), 0.0f);
        } else {
          map_.mean_scores(p, mean.data());
          class_probabilities_.sum(mean.data(), per_class.data());
        }
      }
      if (label == ClassId::Unknown) ++unknown_here;
      labels[i] = static_cast<std::uint8_t>(label);
      for (std::size_t c = 0; c < channels.size(); ++c) channels[c][i] = per_class[c];
    }
    unknown += unknown_here;
  });
  return unknown;
}

void DgcnnMapClassifier::merge(const DgcnnMapClassifier& other, const Pose& other_to_this) {
  map_.merge(other.map_, other_to_this);
  blocks_classified_ += other.blocks_classified_;
  delays_.merge(other.delays_);
  changed_.clear();
}

std::size_t DgcnnMapClassifier::relabel(PointBuffer& points) const {
  std::vector<std::uint32_t> of_point(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const double x = points.x()[i], y = points.y()[i], z = points.z()[i];
      of_point[i] = map_.find(x, y, z);
      if (of_point[i] == LabelledPointMap::kNoPoint) of_point[i] = map_.nearest_classified(x, y, z);
    }
  });
  return label_points(points, of_point);
}

void DgcnnMapClassifier::save_state(StateWriter& out) const {
  out.tag("DMAP");
  out.put<std::uint64_t>(blocks_classified_);
  map_.save_state(out);
  schedule_.save_state(out);
  out.put(scans_);
  delays_.save_state(out);
}

void DgcnnMapClassifier::load_state(StateReader& in) {
  in.expect_tag("DMAP");
  const auto blocks_classified = in.get<std::uint64_t>();
  map_.load_state(in);
  schedule_.load_state(in);
  if (!schedule_.consistent_with(map_.size(), model_.classes())) {
    in.fail("the map blocks name points the labelled point map does not hold, or scores of another class count");
  }
  scans_ = in.get<std::uint32_t>();
  delays_.load_state(in);
  if (!delays_.consistent_with(map_.size(), scans_)) {
    in.fail("the class delays name points the labelled point map does not hold, or later scans");
  }
  blocks_classified_ = blocks_classified;
}

}  // namespace sarmap
