#include "engine/pipeline/point_classifier.hpp"

#include <algorithm>
#include <optional>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/semantic/dgcnn/dgcnn_model.hpp"

namespace sarmap::pipeline {

namespace {

std::size_t count_unknown(const PointBuffer& points) {
  return static_cast<std::size_t>(std::count(points.labels().begin(), points.labels().end(),
                                             static_cast<std::uint8_t>(ClassId::Unknown)));
}

class LabelsClassifier final : public PointClassifier {
 public:
  std::string_view name() const override { return "labels"; }
  ClassifyCounts classify(PointBuffer& points) override {
    if (!points.has_labels() && !points.empty()) {
      throw Error(ErrorCode::InvalidData, "the input has no label property, which --classifier labels needs");
    }
    ClassifyCounts counts;
    if (points.has_labels()) counts.unlabelled = count_unknown(points);
    return counts;
  }
};

class GeometricPointClassifier final : public PointClassifier {
 public:
  explicit GeometricPointClassifier(const GeometricClassifierSettings& settings) : classifier_(settings) {}
  std::string_view name() const override { return "geometric"; }
  ClassifyCounts classify(PointBuffer& points) override {
    classifier_.classify(points);
    ClassifyCounts counts;
    counts.unlabelled = count_unknown(points);
    return counts;
  }

 private:
  GeometricClassifier classifier_;
};

DgcnnMapClassifierSettings map_settings(const ClassifierConfig& config) {
  DgcnnMapClassifierSettings s;
  s.cell = config.map_cell;
  s.stride = config.dgcnn.stride;
  s.min_points = config.dgcnn.min_points;
  s.growth = config.map_growth;
  s.min_new_points = config.map_min_new_points;
  s.max_wait_scans = config.map_max_wait_scans;
  s.seed = config.dgcnn.seed;
  return s;
}

class DgcnnPointClassifier final : public PointClassifier {
 public:
  explicit DgcnnPointClassifier(const ClassifierConfig& config)
      : model_(DgcnnModel::load(config.model)), rules_(config.rules) {
    if (config.per_scan) {
      per_scan_.emplace(model_, config.dgcnn);
    } else {
      on_map_.emplace(model_, map_settings(config));
    }
  }
  std::string_view name() const override { return on_map_ ? "dgcnn-map" : "dgcnn"; }
  const DgcnnMapClassifier* accumulated_map() const override { return on_map_ ? &*on_map_ : nullptr; }
  std::size_t relabel(PointBuffer& points) const override {
    if (!on_map_) return PointClassifier::relabel(points);
    const std::size_t unknown = on_map_->relabel(points);
    rules_.reapply(points);  // moves labels between classes only, never to or from unknown
    return unknown;
  }
  std::size_t finish() override { return on_map_ ? on_map_->finish() : 0; }
  std::size_t forget(const std::function<bool(double, double, double)>& forget) override {
    return on_map_ ? on_map_->forget(forget) : 0;
  }
  void merge(const PointClassifier& other, const Pose& other_to_this) override {
    // Same name, so the same kind (Mapper::merge): on the map both or neither.
    const auto& same_kind = static_cast<const DgcnnPointClassifier&>(other);
    if (on_map_ && same_kind.on_map_) on_map_->merge(*same_kind.on_map_, other_to_this);
  }
  std::size_t memory_bytes() const override {
    return on_map_ ? on_map_->map().memory_bytes() + on_map_->blocks().memory_bytes() : 0;
  }
  ClassifyCounts classify(PointBuffer& points) override {
    ClassifyCounts counts;
    if (on_map_) {
      const DgcnnMapClassifyStats stats = on_map_->classify(points);
      counts.blocks = stats.blocks;
      counts.map_points_added = stats.map_points_added;
    } else {
      counts.blocks = per_scan_->classify(points).blocks;
    }
    counts.rules = rules_.apply(points);
    counts.unlabelled = count_unknown(points);
    return counts;
  }
  void save_state(StateWriter& out) const override {
    PointClassifier::save_state(out);
    rules_.save_state(out);
    if (on_map_) on_map_->save_state(out);
  }
  void load_state(StateReader& in) override {
    PointClassifier::load_state(in);
    rules_.load_state(in);
    if (on_map_) on_map_->load_state(in);
  }

 private:
  DgcnnModel model_;  // declared before the classifiers, which keep a reference to it
  std::optional<DgcnnClassifier> per_scan_;
  std::optional<DgcnnMapClassifier> on_map_;
  RuleChain rules_;
};

}  // namespace

std::size_t PointClassifier::relabel(PointBuffer& points) const {
  return points.has_labels() ? count_unknown(points) : points.size();
}

void PointClassifier::save_state(StateWriter& out) const {
  out.tag("CLSF");
  out.put_string(name());
}

void PointClassifier::load_state(StateReader& in) {
  in.expect_tag("CLSF");
  const std::string saved = in.get_string();
  if (saved != name()) in.fail("the state is the " + saved + " classifier's, this run uses " + std::string(name()));
}

std::string_view to_string(ClassifierKind kind) {
  switch (kind) {
    case ClassifierKind::Dgcnn: return "dgcnn";
    case ClassifierKind::Geometric: return "geometric";
    case ClassifierKind::Labels: return "labels";
  }
  return "unknown";
}

ClassifierKind classifier_kind_from_name(std::string_view name) {
  for (ClassifierKind kind : {ClassifierKind::Dgcnn, ClassifierKind::Geometric, ClassifierKind::Labels}) {
    if (name == to_string(kind)) return kind;
  }
  throw Error(ErrorCode::InvalidArgument, "unknown classifier \"" + std::string(name) +
                                              "\": choose dgcnn (the network), geometric (the normal-based "
                                              "baseline) or labels (the input's label property)");
}

std::unique_ptr<PointClassifier> make_point_classifier(const ClassifierConfig& config) {
  switch (config.kind) {
    case ClassifierKind::Labels: return std::make_unique<LabelsClassifier>();
    case ClassifierKind::Geometric: return std::make_unique<GeometricPointClassifier>(config.geometric);
    case ClassifierKind::Dgcnn:
      if (config.model.empty()) {
        throw Error(ErrorCode::InvalidArgument, "classifier dgcnn needs a model file (--model M.safetensors)");
      }
      return std::make_unique<DgcnnPointClassifier>(config);
  }
  throw Error(ErrorCode::InvalidArgument,
              "unknown classifier kind " + std::to_string(static_cast<int>(config.kind)));
}

}  // namespace sarmap::pipeline
