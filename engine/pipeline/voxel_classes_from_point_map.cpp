#include "engine/pipeline/voxel_classes_from_point_map.hpp"

#include <algorithm>
#include <cstdint>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace sarmap::pipeline {

std::vector<VoxelClassUpdate> voxel_classes_from_point_map(const DgcnnMapClassifier& classifier,
                                                           double inv_resolution) {
  const LabelledPointMap& points = classifier.map();
  const std::vector<ClassId>& classes = classifier.channel_classes();
  const auto voxel_of = [&](std::uint32_t p) {
    return metric::key_of(points.points().x()[p], points.points().y()[p], points.points().z()[p], inv_resolution);
  };
  const std::vector<std::uint32_t>& changed = classifier.changed_points();
  std::vector<std::uint64_t> voxels(changed.size());
  // In parallel, as the classify stage's other steps: a reclassified block
  // changes thousands of points, and each voxel reads only the map.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, changed.size(), 8192),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k != r.end(); ++k) voxels[k] = metric::pack(voxel_of(changed[k]));
                    });
  tbb::parallel_sort(voxels.begin(), voxels.end());
  voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
  // One slot per voxel, in voxel order; a voxel none of whose points has a
  // class yet keeps points == 0 and is left out below.
  std::vector<VoxelClassUpdate> updates(voxels.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, voxels.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<float> mean(classes.size());
                      for (std::size_t v = r.begin(); v != r.end(); ++v) {
                        const metric::VoxelKey key = metric::unpack_voxel(voxels[v]);
                        const std::int64_t voxel[3] = {key.x, key.y, key.z};
                        // One observation of the voxel's map points, each with its mean scores.
                        metric::ClassObservation& observation = updates[v].observation;
                        updates[v].key = key;
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
                        observation.has_scores = observation.points > 0;
                      }
                    });
  std::erase_if(updates, [](const VoxelClassUpdate& u) { return u.observation.points == 0; });
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
