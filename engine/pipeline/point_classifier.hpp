// The classify stage: where each point's class comes from. One interface over
// the three sources a run can choose:
//   dgcnn      the network (a safetensors model) — the default
//   geometric  the normal- and height-based baseline, no model needed
//   labels     the input's own label property (simulated or annotated data)
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "engine/core/point_buffer.hpp"
#include "engine/core/pose.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/semantic/dgcnn/dgcnn_classifier.hpp"
#include "engine/semantic/geometric/geometric_classifier.hpp"
#include "engine/semantic/map/dgcnn_map_classifier.hpp"
#include "engine/semantic/rules/rule_chain.hpp"

namespace sarmap::pipeline {

// The network's settings in the pipeline: blocks of at least 100 points, not
// the network's own 500 (DgcnnClassifierSettings, `sarmap classify`): one
// depth frame leaves many blocks at its edges with a few hundred points, and
// the network labels them well (the held-out figures: docs/perf-history.md).
inline DgcnnClassifierSettings pipeline_dgcnn_settings() {
  DgcnnClassifierSettings settings;
  settings.min_points = 100;
  return settings;
}

// Where point classes come from: the DGCNN, the geometric baseline, or the
// input's label property.
enum class ClassifierKind : std::uint8_t { Dgcnn, Geometric, Labels };

// "dgcnn", "geometric" or "labels".
std::string_view to_string(ClassifierKind kind);
// The kind a name stands for; throws sarmap::Error (InvalidArgument) naming
// the choices for any other name.
ClassifierKind classifier_kind_from_name(std::string_view name);

struct ClassifierConfig {
  ClassifierKind kind = ClassifierKind::Dgcnn;
  std::filesystem::path model;  // dgcnn only; required for it
  DgcnnClassifierSettings dgcnn = pipeline_dgcnn_settings();
  // dgcnn: classify each scan on its own instead of the accumulated map
  // (engine/semantic/map/dgcnn_map_classifier.hpp), whose cell and growth
  // come from map_cell, map_growth, map_min_new_points and
  // map_max_wait_scans; the stride, minimum points and seed above serve both.
  bool per_scan = false;
  double map_cell = 0.025;
  double map_growth = 0.25;
  std::size_t map_min_new_points = 512;
  std::size_t map_max_wait_scans = 20;
  // dgcnn: the rules that correct the network's labels, in their order
  // (engine/semantic/rules/rule_chain.hpp), on each scan and on the kept
  // points relabelled from the map.
  RuleChainSettings rules;
  GeometricClassifierSettings geometric;
};

// What one call did, for the profile's counters.
struct ClassifyCounts {
  std::size_t blocks = 0;          // dgcnn blocks run
  std::size_t unlabelled = 0;      // points left unknown (sparse blocks, far points)
  RuleChanges rules;               // dgcnn: the labels each rule changed
  std::size_t map_points_added = 0;  // dgcnn on the map: points the labelled point map gained
};

class PointClassifier {
 public:
  virtual ~PointClassifier() = default;
  virtual std::string_view name() const = 0;
  // Sets points.labels() to predicted class ids (and per-class scores where the
  // classifier has them). Throws sarmap::Error naming what the input lacks.
  // Not const: a classifier may remember what earlier scans of the sequence showed.
  virtual ClassifyCounts classify(PointBuffer& points) = 0;
  // Whether a point's class may come after its scan and change later (the
  // classifier of the accumulated map): what keeps labels then takes them
  // from relabel() when it needs them final.
  virtual bool labels_arrive_late() const { return accumulated_map() != nullptr; }
  // The classifier of the accumulated map when that is where classes come
  // from, else nullptr: the Mapper takes the metric map's voxel classes from it.
  virtual const DgcnnMapClassifier* accumulated_map() const { return nullptr; }
  // Sets the labels and scores of points already seen from what the
  // classifier knows now, the rules applied again; returns how many stay
  // unknown. Only for classifiers whose labels arrive late; the others
  // leave `points` as is.
  virtual std::size_t relabel(PointBuffer& points) const;
  // The scans have ended: label what still waits for more of them (the
  // classifier of the accumulated map's unfinished blocks). Returns the
  // blocks classified; nothing to do for the others.
  virtual std::size_t finish() { return 0; }
  // Lets go of what it keeps at the positions where `forget` is true (a
  // bounded map's dropped region); returns how many points. Nothing kept:
  // nothing to do.
  virtual std::size_t forget(const std::function<bool(double, double, double)>& forget) {
    (void)forget;
    return 0;
  }
  // Takes what `other`, a classifier of the same kind (Mapper::merge checks),
  // keeps, carried into this one's frame: the labelled point maps merge by
  // cell. Nothing kept: nothing to merge.
  virtual void merge(const PointClassifier& other, const Pose& other_to_this) {
    (void)other, (void)other_to_this;
  }
  // Bytes of what the classifier keeps between scans (its labelled point map).
  virtual std::size_t memory_bytes() const { return 0; }
  // What it remembers of earlier scans, for a checkpoint
  // (engine/core/state_stream.hpp); its name, then nothing for a classifier
  // that remembers nothing.
  virtual void save_state(StateWriter& out) const;
  // Throws sarmap::Error (Parse) naming the offset for another classifier's
  // state or a damaged one.
  virtual void load_state(StateReader& in);
};

// Throws sarmap::Error: InvalidArgument for an unknown kind or a dgcnn without
// a model path; the model loader's errors for a bad model file.
std::unique_ptr<PointClassifier> make_point_classifier(const ClassifierConfig& config);

}  // namespace sarmap::pipeline
