// Blocks run in parallel (one workspace per thread); their scores are then
// accumulated serially in block order so the result is thread-count independent.
#include "engine/semantic/dgcnn/dgcnn_classifier.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/semantic/dgcnn/block_features.hpp"
#include "engine/semantic/dgcnn/block_partition.hpp"
#include "engine/semantic/dgcnn/block_sampling.hpp"
#include "engine/semantic/dgcnn/score_carry_back.hpp"

namespace sarmap {

const DgcnnModel& require_labelling_metadata(const DgcnnModel& model) {
  const DgcnnMetadata& m = model.metadata();
  if (!m.has_preprocessing()) {
    throw Error(ErrorCode::InvalidData, "DGCNN model lacks the sarmap.normalisation / sarmap.classes metadata "
                                        "needed to label clouds");
  }
  if (m.classes.size() != model.classes()) {
    throw Error(ErrorCode::InvalidData, "DGCNN model metadata names " + std::to_string(m.classes.size()) +
                                            " classes but the network has " + std::to_string(model.classes()) + " logits");
  }
  if (model.channels() != 6 && model.channels() != 9) {
    throw Error(ErrorCode::Unsupported, "DGCNN model with " + std::to_string(model.channels()) +
                                            " input channels; block features give 6 or 9");
  }
  return model;
}

DgcnnClassifier::DgcnnClassifier(const DgcnnModel& model, DgcnnClassifierSettings settings)
    : model_(require_labelling_metadata(model)),
      settings_(settings),
      class_probabilities_(model.metadata().classes) {}

DgcnnClassifyStats DgcnnClassifier::classify(PointBuffer& points) const {
  const DgcnnMetadata& m = model_.metadata();
  const bool rgb = model_.channels() == 9;
  if (rgb && !points.has_colors()) {
    throw Error(ErrorCode::InvalidArgument, "the DGCNN model takes colours (9 channels) but the cloud has none");
  }
  BlockPartitionSettings ps;
  ps.block_size = m.block_size;
  ps.stride = settings_.stride > 0.0 ? settings_.stride : kDefaultStrideFraction * m.block_size;
  ps.min_points = settings_.min_points;
  const BlockPartition part = partition_blocks(points, ps);
  const std::size_t classes = model_.classes(), target = m.points_per_block;

  std::vector<std::vector<std::uint32_t>> samples(part.blocks.size());
  std::vector<std::vector<float>> scores(part.blocks.size());
  const auto classify_block = [&](std::size_t b) {
    const Block& block = part.blocks[b];
    samples[b] = sample_block(block.points.size(), target, settings_.seed, b);
    std::vector<std::uint32_t> indices(samples[b].size());
    for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = block.points[samples[b][i]];
    BlockFrame frame{block.origin_x, block.origin_y, block.size, m.z_min, m.z_max};
    const std::vector<float> features = block_features(points, indices, frame, rgb);
    std::vector<float>& s = scores[b];
    s.resize(indices.size() * classes);
    DgcnnWorkspacePool::Loan workspace = workspaces_.borrow();
    model_.forward(features.data(), indices.size(), s.data(), workspace.get());
    for (std::size_t i = 0; i < indices.size(); ++i) {  // softmax per row
      float* row = s.data() + i * classes;
      const float top = *std::max_element(row, row + classes);
      double sum = 0.0;
      for (std::size_t c = 0; c < classes; ++c) sum += (row[c] = std::exp(row[c] - top));
      for (std::size_t c = 0; c < classes; ++c) row[c] = static_cast<float>(row[c] / sum);
    }
  };
  tbb::parallel_for(std::size_t{0}, part.blocks.size(), classify_block);

  ScoreAccumulator acc(points.size(), classes);
  for (std::size_t b = 0; b < part.blocks.size(); ++b) acc.add_block(points, part.blocks[b], samples[b], scores[b]);

  points.enable_labels();
  const std::vector<ClassId>& out_classes = class_probabilities_.classes();
  std::vector<std::size_t> channels(out_classes.size());
  for (std::size_t c = 0; c < out_classes.size(); ++c) {
    const std::string name(class_info(out_classes[c]).name);
    const std::size_t existing = points.find_score(name);
    channels[c] = existing < points.score_count() ? existing : points.add_score(name);
  }
  // Each point's mean scores and label: in parallel, scratch rows per range.
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, points.size(), 4096),
      [&](const tbb::blocked_range<std::size_t>& range) {
        std::vector<float> mean(classes), per_class(out_classes.size());
        for (std::size_t p = range.begin(); p != range.end(); ++p) {
          acc.mean(p, mean.data());
          class_probabilities_.sum(mean.data(), per_class.data());
          for (std::size_t c = 0; c < channels.size(); ++c) points.score(channels[c])[p] = per_class[c];
          points.labels()[p] = static_cast<std::uint8_t>(
              acc.hits(p) == 0 ? ClassId::Unknown : out_classes[class_probabilities_.best(per_class.data())]);
        }
      });
  return {part.blocks.size(), part.dropped_points};
}

}  // namespace sarmap
