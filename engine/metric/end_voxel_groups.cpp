#include "engine/metric/end_voxel_groups.hpp"

#include <algorithm>
#include <string>

#include "engine/core/capacity_bytes.hpp"
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

ClassSource ClassSource::of(const PointBuffer& points, bool use_scores) {
  ClassSource source;
  if (points.has_labels()) source.labels = points.labels();
  if (!use_scores) return source;
  for (const ClassInfo& info : kClassTable) {
    const std::size_t c = points.find_score(std::string(info.name));
    if (c == points.score_count()) {
      source.scores.clear();
      break;
    }
    source.scores.push_back(points.score(c));
  }
  return source;
}

LocalEndGroups::LocalEndGroups() : cache_(std::size_t{1} << kCacheBits) {}

void LocalEndGroups::clear() {
  std::fill(cache_.begin(), cache_.end(), Slot{});
  keys_.clear();
  observations_.clear();
  box_ = {};
}

std::size_t LocalEndGroups::memory_bytes() const {
  return capacity_bytes(cache_) + capacity_bytes(keys_) + capacity_bytes(observations_);
}

std::size_t EndVoxelGroups::memory_bytes() const {
  return capacity_bytes(keys_) + capacity_bytes(observations_) + hashed_.memory_bytes() +
         capacity_bytes(dense_);
}

void EndVoxelGroups::merge(std::span<const LocalEndGroups> stretches, std::size_t max_dense_cells,
                           const std::function<void(std::size_t)>& progress) {
  keys_.clear();
  observations_.clear();
  VoxelBox box;
  std::size_t most = 0;
  for (const LocalEndGroups& stretch : stretches) {
    box.add(stretch.box());
    most += stretch.keys().size();
  }
  // Room for every group up front: keys already final never move while a
  // reader given them by progress goes on.
  reserve_whole_huge_pages(keys_, most);
  reserve_whole_huge_pages(observations_, most);
  // Folds every stretch's groups, in order, into the global group whose
  // index global_index(key) gives (the next index opens a new group).
  const auto fold_all = [&](auto&& global_index) {
    for (const LocalEndGroups& stretch : stretches) {
      for (std::size_t g = 0; g < stretch.keys().size(); ++g) {
        const VoxelKey& key = stretch.keys()[g];
        const std::uint32_t u = global_index(key);
        if (u == keys_.size()) {
          keys_.push_back(key);
          observations_.push_back(stretch.observations()[g]);
          if (progress && keys_.size() % kProgressGroups == 0) progress(keys_.size());
        } else {
          observations_[u].add(stretch.observations()[g]);
        }
      }
      if (progress) progress(keys_.size());
    }
  };

  const std::size_t cells = box.cells();
  used_dense_ = cells != 0 && cells <= max_dense_cells;
  if (used_dense_) {
    if (dense_.size() < cells) {
      resize_in_whole_huge_pages(dense_, cells);
    }
    const std::size_t ex = static_cast<std::size_t>(box.hi.x - box.lo.x + 1);
    const std::size_t exy = ex * static_cast<std::size_t>(box.hi.y - box.lo.y + 1);
    const auto cell_of = [&](const VoxelKey& k) {
      return static_cast<std::size_t>(k.x - box.lo.x) + ex * static_cast<std::size_t>(k.y - box.lo.y) +
             exy * static_cast<std::size_t>(k.z - box.lo.z);
    };
    fold_all([&](const VoxelKey& key) {
      std::uint32_t& slot = dense_[cell_of(key)];
      if (slot == 0) slot = static_cast<std::uint32_t>(keys_.size()) + 1;
      return slot - 1;
    });
    for (const VoxelKey& key : keys_) dense_[cell_of(key)] = 0;
  } else {
    hashed_.clear();
    fold_all([&](const VoxelKey& key) { return hashed_.find_or_insert(pack(key)); });
  }
}

}  // namespace sarmap::metric
