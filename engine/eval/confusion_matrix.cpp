#include "engine/eval/confusion_matrix.hpp"

namespace sarmap::eval {

void ConfusionMatrix::merge(const ConfusionMatrix& other) {
  for (std::size_t t = 0; t < kClassCount; ++t) {
    for (std::size_t p = 0; p < kClassCount; ++p) counts_[t][p] += other.counts_[t][p];
  }
}

std::uint64_t ConfusionMatrix::total() const {
  std::uint64_t sum = 0;
  for (const auto& row : counts_) {
    for (std::uint64_t v : row) sum += v;
  }
  return sum;
}

std::uint64_t ConfusionMatrix::truth_total(ClassId c) const {
  std::uint64_t sum = 0;
  for (std::uint64_t v : counts_[index(c)]) sum += v;
  return sum;
}

std::uint64_t ConfusionMatrix::predicted_total(ClassId c) const {
  std::uint64_t sum = 0;
  for (const auto& row : counts_) sum += row[index(c)];
  return sum;
}

std::optional<double> ConfusionMatrix::accuracy() const {
  const std::uint64_t n = total();
  if (n == 0) return std::nullopt;
  std::uint64_t correct = 0;
  // Unknown (0) is "could not label": even against an unknown truth it is wrong.
  for (std::size_t c = 1; c < kClassCount; ++c) correct += counts_[c][c];
  return static_cast<double>(correct) / static_cast<double>(n);
}

std::optional<double> ConfusionMatrix::iou(ClassId c) const {
  const std::uint64_t tp = count(c, c);
  const std::uint64_t denominator = truth_total(c) + predicted_total(c) - tp;
  if (denominator == 0) return std::nullopt;
  return static_cast<double>(tp) / static_cast<double>(denominator);
}

std::optional<double> ConfusionMatrix::precision(ClassId c) const {
  const std::uint64_t p = predicted_total(c);
  if (p == 0) return std::nullopt;
  return static_cast<double>(count(c, c)) / static_cast<double>(p);
}

std::optional<double> ConfusionMatrix::recall(ClassId c) const {
  const std::uint64_t t = truth_total(c);
  if (t == 0) return std::nullopt;
  return static_cast<double>(count(c, c)) / static_cast<double>(t);
}

std::optional<double> ConfusionMatrix::mean_iou(std::span<const ClassId> classes) const {
  double sum = 0;
  int defined = 0;
  for (ClassId c : classes) {
    if (const auto v = iou(c)) {
      sum += *v;
      ++defined;
    }
  }
  if (defined == 0) return std::nullopt;
  return sum / defined;
}

}  // namespace sarmap::eval
