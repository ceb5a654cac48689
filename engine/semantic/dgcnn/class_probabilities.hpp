// Turns a row of a model's per-logit probabilities into per-sarmap-class
// probabilities, for a model whose logits map to sarmap's classes many to one
// (an S3DIS model's ceiling, beam, door, ... all count as other). Both DGCNN
// classifiers and the metric map's evidence use it, so they label alike:
// a class's probability is the sum of its logits', the label their arg-max.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/classes.hpp"

namespace sarmap {

class ClassProbabilities {
 public:
  // `logit_classes`: the sarmap class of each logit (DgcnnMetadata::classes).
  explicit ClassProbabilities(std::span<const ClassId> logit_classes) {
    for (std::size_t v = 1; v < kClassCount; ++v) {
      const auto c = static_cast<ClassId>(v);
      for (const ClassId l : logit_classes) {
        if (l == c) {
          classes_.push_back(c);
          break;
        }
      }
    }
    for (const ClassId l : logit_classes) {
      std::size_t slot = 0;
      while (classes_[slot] != l) ++slot;
      slot_.push_back(static_cast<std::uint8_t>(slot));
    }
  }

  std::size_t logits() const { return slot_.size(); }
  // The sarmap classes some logit maps to, by ascending class id: the score
  // channels a classified point carries, in order.
  const std::vector<ClassId>& classes() const { return classes_; }

  // out[i] = the sum of row[l] over the logits l that map to classes()[i].
  template <class T>
  void sum(const T* row, T* out) const {
    for (std::size_t i = 0; i < classes_.size(); ++i) out[i] = T{};
    for (std::size_t l = 0; l < slot_.size(); ++l) out[slot_[l]] += row[l];
  }
  // The index into classes() of the highest of class_row (the lowest class
  // id on ties).
  template <class T>
  std::size_t best(const T* class_row) const {
    std::size_t b = 0;
    for (std::size_t i = 1; i < classes_.size(); ++i) {
      if (class_row[i] > class_row[b]) b = i;
    }
    return b;
  }

 private:
  std::vector<ClassId> classes_;
  std::vector<std::uint8_t> slot_;  // logit -> index into classes_
};

}  // namespace sarmap
