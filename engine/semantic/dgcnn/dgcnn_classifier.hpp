// Labels a whole scan with the DGCNN: partition into blocks, sample and
// featurise each, run the network per block, carry scores back to every point.
#pragma once

#include <cstddef>
#include <cstdint>

#include "engine/core/point_buffer.hpp"
#include "engine/semantic/dgcnn/class_probabilities.hpp"
#include "engine/semantic/dgcnn/dgcnn_model.hpp"
#include "engine/semantic/dgcnn/dgcnn_workspace_pool.hpp"

namespace sarmap {

// Blocks overlap by a quarter unless told otherwise: each point near a
// block's edge is also seen nearer the middle of a neighbouring block, and
// its scores are averaged over both. It costs more blocks per scan and buys
// accuracy; both figures are in PERF.md, "Classifiers".
inline constexpr double kDefaultStrideFraction = 0.75;

struct DgcnnClassifierSettings {
  double stride = 0.0;           // metres between block origins; <= 0: kDefaultStrideFraction x the block size
  std::size_t min_points = 500;  // sparser blocks are dropped
  std::uint64_t seed = 1;        // sampling seed; results do not depend on threads
};

// Throws sarmap::Error unless `model` can label clouds: its preprocessing
// metadata, one class per logit, and 6 or 9 input channels. Returns it.
const DgcnnModel& require_labelling_metadata(const DgcnnModel& model);

struct DgcnnClassifyStats {
  std::size_t blocks = 0;
  std::size_t dropped_points = 0;  // only in dropped blocks: labelled unknown
};

class DgcnnClassifier {
 public:
  // Throws sarmap::Error when the model lacks the preprocessing metadata.
  DgcnnClassifier(const DgcnnModel& model, DgcnnClassifierSettings settings);

  // Sets labels (sarmap class ids) and one score channel per sarmap class
  // the model's logits map to (named after the class: the sum of those
  // logits' softmax probabilities, averaged over blocks) on `points`; the
  // label is the arg-max of those channels (ClassProbabilities). A 9-channel
  // model needs colours. Runs in the caller's TBB arena; calls from several
  // threads at once are safe (each block borrows its own workspace).
  DgcnnClassifyStats classify(PointBuffer& points) const;

 private:
  const DgcnnModel& model_;
  DgcnnClassifierSettings settings_;
  ClassProbabilities class_probabilities_;
  // Forward-pass buffers kept between calls (a scan's blocks would
  // otherwise allocate and zero them again for every scan).
  mutable DgcnnWorkspacePool workspaces_;
};

}  // namespace sarmap
