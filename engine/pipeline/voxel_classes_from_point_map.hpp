// Where classes come from the accumulated map, the metric map's voxel
// classes follow its points: the voxels holding map points that the last
// classification added or classified again take their class evidence from
// one observation of all their map points' mean scores (a point not
// classified yet stands in with the neighbour whose class it borrows).
//
// Two steps, so that the classify stage of one scan can run while the metric
// stage takes the previous one (Mapper::integrate_stream): the observations
// are read from the classifier right after it ran, and written into the
// metric map after that scan's rays.
#pragma once

#include <cstddef>
#include <vector>

#include "engine/core/bounds.hpp"
#include "engine/metric/label_fusion.hpp"
#include "engine/metric/metric_map.hpp"
#include "engine/metric/voxel_key.hpp"
#include "engine/semantic/map/dgcnn_map_classifier.hpp"

namespace sarmap::pipeline {

struct VoxelClassUpdate {
  metric::VoxelKey key;
  metric::ClassObservation observation;
};

// One update per voxel (of the metric map's inverse resolution
// `inv_resolution`) holding a map point of the classifier's last
// changed_points() that has scores; reads only the classifier.
std::vector<VoxelClassUpdate> voxel_classes_from_point_map(const DgcnnMapClassifier& classifier,
                                                           double inv_resolution);

// Replaces the evidence of the voxels the map knows (the others keep none);
// returns how many changed, and `changed_region` grows by their centres
// (the topological map must look there again).
std::size_t apply_voxel_classes(const std::vector<VoxelClassUpdate>& updates, metric::MetricMap& map,
                                Bounds& changed_region);

}  // namespace sarmap::pipeline
