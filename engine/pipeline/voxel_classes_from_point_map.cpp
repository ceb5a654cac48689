#include "engine/pipeline/voxel_classes_from_point_map.hpp"

#include <algorithm>
#include <cstdint>

namespace sarmap::pipeline {

std::vector<VoxelClassUpdate> voxel_classes_from_point_map(const DgcnnMapClassifier& classifier,
                                                           double inv_resolution) {
  const LabelledPointMap& points = classifier.map();
  const std::vector<ClassId>& classes = classifier.channel_classes();
  const auto voxel_of = [&](std::uint32_t p) {
    return metric::key_of(points.points().x()[p], points.points().y()[p], points.points().z()[p], inv_resolution);
  };
  std::vector<std::uint64_t> voxels;
  voxels.reserve(classifier.changed_points().size());
  for (const std::uint32_t p : classifier.changed_points()) voxels.push_back(metric::pack(voxel_of(p)));
  std::sort(voxels.begin(), voxels.end());
  voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
  std::vector<float> mean(classes.size());
  std::vector<VoxelClassUpdate> updates;
  updates.reserve(voxels.size());
  for (const std::uint64_t word : voxels) {
    const metric::VoxelKey key = metric::unpack_voxel(word);
    const std::int64_t voxel[3] = {key.x, key.y, key.z};
    // One observation of the voxel's map points, each with its mean scores.
    metric::ClassObservation observation;
    points.for_each_in_voxel(voxel, inv_resolution, [&](std::uint32_t p) {
      const std::uint32_t scored = points.scored_point(p);
      if (scored == LabelledPointMap::kNoPoint) return;
      points.mean_scores(scored, mean.data());
      // The label by the classifiers' own rule (several logits may share a class).
      ++observation.counts[static_cast<std::size_t>(classifier.map_point_class(scored))];
      for (std::size_t c = 0; c < classes.size(); ++c) {
        observation.score_sums[static_cast<std::size_t>(classes[c])] += mean[c];
      }
      ++observation.points;
    });
    if (observation.points == 0) continue;
    observation.has_scores = true;
    updates.push_back({key, observation});
  }
  return updates;
}

std::size_t apply_voxel_classes(const std::vector<VoxelClassUpdate>& updates, metric::MetricMap& map,
                                Bounds& changed_region) {
  std::size_t changed = 0;
  for (const VoxelClassUpdate& u : updates) {
    if (map.replace_evidence(u.key, u.observation)) {
      ++changed;
      changed_region.extend(map.center_of(u.key));
    }
  }
  return changed;
}

}  // namespace sarmap::pipeline
