// A confusion matrix over sarmap's classes (rows: ground truth, columns:
// prediction) and the figures derived from it: accuracy, per-class IoU,
// precision, recall, mean IoU over a chosen set of classes.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "engine/core/classes.hpp"

namespace sarmap::eval {

// The four classes the maps are about; mean_iou averages over these.
inline constexpr std::array<ClassId, 4> kMappingClasses{ClassId::Terrain, ClassId::Wall, ClassId::InclinedRamp,
                                                        ClassId::FlatRamp};

class ConfusionMatrix {
 public:
  void add(ClassId truth, ClassId predicted, std::uint64_t count = 1) {
    counts_[index(truth)][index(predicted)] += count;
  }
  void merge(const ConfusionMatrix& other);

  std::uint64_t count(ClassId truth, ClassId predicted) const { return counts_[index(truth)][index(predicted)]; }
  std::uint64_t total() const;
  std::uint64_t truth_total(ClassId c) const;      // row sum
  std::uint64_t predicted_total(ClassId c) const;  // column sum

  // Correct / total; nullopt when empty. A prediction of Unknown is never correct.
  std::optional<double> accuracy() const;
  // TP / (TP + FP + FN); nullopt when the class is neither present nor predicted.
  std::optional<double> iou(ClassId c) const;
  std::optional<double> precision(ClassId c) const;  // TP / predicted
  std::optional<double> recall(ClassId c) const;     // TP / truth
  // Mean of the defined IoUs of the given classes; nullopt when none is defined.
  std::optional<double> mean_iou(std::span<const ClassId> classes = kMappingClasses) const;

 private:
  static std::size_t index(ClassId c) { return static_cast<std::size_t>(c); }
  std::array<std::array<std::uint64_t, kClassCount>, kClassCount> counts_{};
};

}  // namespace sarmap::eval
