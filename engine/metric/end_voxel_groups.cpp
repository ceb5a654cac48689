#include "engine/metric/end_voxel_groups.hpp"

#include <algorithm>
#include <string>

#include "engine/core/classes.hpp"

namespace sarmap::metric {

std::size_t VoxelBox::cells() const {
  if (empty()) return 0;
  // Each extent is below 2^22 (keys are within +-2^21), so two multiply
  // without overflow; the third may not, hence the check.
  const auto ex = static_cast<std::size_t>(std::int64_t{hi.x} - lo.x + 1);
  const auto ey = static_cast<std::size_t>(std::int64_t{hi.y} - lo.y + 1);
  const auto ez = static_cast<std::size_t>(std::int64_t{hi.z} - lo.z + 1);
  const std::size_t xy = ex * ey;
  return xy > std::numeric_limits<std::size_t>::max() / ez ? std::numeric_limits<std::size_t>::max() : xy * ez;
}

namespace {

// Score channels for all classes, by class id, or empty when any is missing.
std::vector<std::span<const float>> class_score_channels(const PointBuffer& points) {
  std::vector<std::span<const float>> channels;
  for (const ClassInfo& info : kClassTable) {
    const std::size_t c = points.find_score(std::string(info.name));
    if (c == points.score_count()) return {};
    channels.push_back(points.score(c));
  }
  return channels;
}

// Folds point i into obs: its scores when there are score channels, else its label.
void add_observation(ClassObservation& obs, std::size_t i, const std::vector<std::span<const float>>& scores,
                     std::span<const std::uint8_t> labels) {
  ++obs.points;
  std::size_t label = 0;
  if (!scores.empty()) {
    obs.has_scores = true;
    float best = -1.0f;
    for (std::size_t c = 0; c < kClassCount; ++c) {
      const float s = scores[c][i];
      obs.score_sums[c] += s;
      if (s > best) best = s, label = c;
    }
  } else if (!labels.empty()) {
    label = labels[i];
  }
  if (obs.counts[label] < 0xffff) ++obs.counts[label];
}

}  // namespace

void EndVoxelGroups::group(const PointBuffer& points, double inv_resolution, std::span<const std::uint8_t> ends,
                           const VoxelBox& box, bool use_scores, std::size_t max_dense_cells) {
  keys_.clear();
  observations_.clear();
  const auto scores = use_scores ? class_score_channels(points) : std::vector<std::span<const float>>{};
  const auto xs = points.x(), ys = points.y(), zs = points.z();
  const std::span<const std::uint8_t> labels =
      points.has_labels() ? points.labels() : std::span<const std::uint8_t>{};
  // Appends a new group for key; returns its index.
  const auto open_group = [&](const VoxelKey& key) {
    keys_.push_back(key);
    observations_.emplace_back();
    return static_cast<std::uint32_t>(keys_.size() - 1);
  };

  const std::size_t cells = box.cells();
  used_dense_ = cells != 0 && cells <= max_dense_cells;
  if (used_dense_) {
    if (dense_.size() < cells) dense_.resize(cells, 0);
    const std::size_t ex = static_cast<std::size_t>(box.hi.x - box.lo.x + 1);
    const std::size_t exy = ex * static_cast<std::size_t>(box.hi.y - box.lo.y + 1);
    const auto cell_of = [&](const VoxelKey& k) {
      return static_cast<std::size_t>(k.x - box.lo.x) + ex * static_cast<std::size_t>(k.y - box.lo.y) +
             exy * static_cast<std::size_t>(k.z - box.lo.z);
    };
    for (std::size_t i = 0; i < ends.size(); ++i) {
      if (!ends[i]) continue;
      const VoxelKey key = key_of(xs[i], ys[i], zs[i], inv_resolution);
      std::uint32_t& slot = dense_[cell_of(key)];
      if (slot == 0) slot = open_group(key) + 1;
      add_observation(observations_[slot - 1], i, scores, labels);
    }
    for (const VoxelKey& key : keys_) dense_[cell_of(key)] = 0;
  } else {
    hashed_.clear();
    for (std::size_t i = 0; i < ends.size(); ++i) {
      if (!ends[i]) continue;
      const VoxelKey key = key_of(xs[i], ys[i], zs[i], inv_resolution);
      const std::uint32_t u = hashed_.find_or_insert(pack(key));
      if (u == keys_.size()) open_group(key);
      add_observation(observations_[u], i, scores, labels);
    }
  }
}

}  // namespace sarmap::metric
