// Where classes come from the accumulated map, the metric map's voxel
// classes follow its points: the voxels holding map points that the last
// classification added or classified again take their class evidence from
// one observation of all their map points' mean scores (a point not
// classified yet stands in with the neighbour whose class it borrows).
#pragma once

#include <cstddef>

#include "engine/core/bounds.hpp"
#include "engine/metric/metric_map.hpp"
#include "engine/semantic/map/dgcnn_map_classifier.hpp"

namespace sarmap::pipeline {

// Returns how many voxels changed; `changed_region` grows by their centres
// (the topological map must look there again). Voxels the map does not know
// keep no evidence.
std::size_t take_voxel_classes_from_point_map(const DgcnnMapClassifier& classifier, metric::MetricMap& map,
                                              Bounds& changed_region);

}  // namespace sarmap::pipeline
