// Scores a metric map voxel by voxel against an arena's ground-truth voxels at
// the same resolution: occupied precision / recall / F1 (strict, and within one
// voxel for sensor noise), free-space accuracy, and the class of occupied voxels.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "engine/eval/confusion_matrix.hpp"
#include "engine/metric/metric_map.hpp"
#include "engine/sim/ground_truth_grid.hpp"

namespace sarmap::eval {

// Counts behind the voxel figures. "Within one voxel" means a match anywhere
// in the 3 x 3 x 3 voxels around: a noisy depth puts a surface's hits one
// voxel off, and a surface on a voxel face is truth on both sides of it.
struct VoxelScores {
  double resolution = 0;
  std::size_t map_occupied = 0, map_free = 0;
  std::size_t truth_occupied = 0;  // every surface voxel of the arena
  std::size_t truth_observed = 0;  // of those, the ones a noise-free ray of the trajectory ends in
  std::size_t truth_free = 0;      // crossed by a noise-free ray, holding no surface

  // Precision: map occupied voxels that are truth occupied (strict / within one).
  std::size_t occupied_correct = 0, occupied_correct_within_1 = 0;
  // Recall: observed truth voxels the map calls occupied (strict / within one).
  // Unobserved surface (behind walls, under ramps) is not held against the map.
  std::size_t observed_found = 0, observed_found_within_1 = 0;
  // Truth free voxels the map calls free; map free voxels that are truth free,
  // and map free voxels that hold a surface (carved by noisy rays).
  std::size_t free_found = 0, map_free_truth_free = 0, map_free_on_surface = 0;
  // Class of every strictly matched occupied voxel: rows truth, columns the map's class.
  ConfusionMatrix classes;

  std::optional<double> precision() const;
  std::optional<double> recall() const;
  std::optional<double> f1() const;
  std::optional<double> precision_within_1() const;
  std::optional<double> recall_within_1() const;
  std::optional<double> f1_within_1() const;
  // Of truth free voxels, the fraction the map calls free.
  std::optional<double> free_accuracy() const;
  // Of the map's free voxels, the fraction truth free.
  std::optional<double> free_precision() const;
  // Of strictly matched occupied voxels, the fraction with the truth's class.
  std::optional<double> class_accuracy() const;
};

// Throws sarmap::Error(InvalidArgument) unless the resolutions agree (to 1e-9 m).
// Costs a pass over the map's blocks plus a few hash look-ups per truth voxel.
VoxelScores score_voxels(const metric::MetricMap& map, const sim::GroundTruthGrid& truth);

// The figures under plain keys (voxel_precision, voxel_recall, voxel_f1,
// *_within_1, free_accuracy, free_precision, voxel_class_accuracy, counts),
// added to `out`; null for a figure with nothing to count.
void add_voxel_scores_json(const VoxelScores& scores, nlohmann::ordered_json& out);
// A few lines of table for `sarmap eval`.
std::string format_voxel_scores(const VoxelScores& scores);

}  // namespace sarmap::eval
