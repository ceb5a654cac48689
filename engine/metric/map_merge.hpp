// Merging two metric maps of one frame voxel by voxel: several robots'
// maps of one building, or the maps of a sequence's parts mapped apart.
// Occupancy log-odds add and clamp, as a new observation does; class
// evidence combines by the map's fusion rule (Bayesian log-odds add and
// clamp, histogram counts add, halving to fit). A voxel known in one map
// only takes that map's value, so merging the maps of disjoint parts of a
// sequence equals mapping it whole wherever the parts' voxels do not
// overlap. Where both know a voxel, the order of updates matters because
// of the clamps: with A the earlier part and B the later, both the merged
// log-odds and the whole sequence's lie between B's and B's plus A's (the
// clamped walk over B's updates is monotone and moves by at most the
// distance of its start), so they differ by at most |A's log-odds|, and
// not at all when neither clamped; the whole sequence's evidence has also
// decayed where B saw the voxel free, which a merge does not redo
// (docs/architecture.md, "Merging maps").
#pragma once

#include <cstddef>

#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

struct MergeCounts {
  std::size_t blocks_added = 0;   // blocks only `other` had
  std::size_t blocks_merged = 0;  // blocks both had
  std::size_t voxels_in_both = 0; // voxels both knew: where the order of updates matters
};

// Throws what merge_into would for maps it cannot merge (settings that
// differ), without changing either: for callers that check before they start.
void check_mergeable(const MetricMap& into, const MetricMap& other);

// Adds `other`'s voxels into `into`. Both maps must have the same settings
// (resolution, occupancy, class fusion): otherwise throws sarmap::Error
// (InvalidArgument) naming the setting and both values, and `into` is
// unchanged. The result does not depend on which map is `into`.
MergeCounts merge_into(MetricMap& into, const MetricMap& other);

// One voxel's merge, for the map's blocks and for tests against it.
SemanticVoxel merge_voxels(const SemanticVoxel& a, const SemanticVoxel& b, const OccupancyModel& occupancy,
                           const LabelFusion& fusion);

}  // namespace sarmap::metric
