// The metric map: its blocks of semantic voxels (semantic_blocks.hpp) plus
// the models that give their numbers meaning (resolution, occupancy, class
// fusion), and the point queries every later stage uses (state,
// probability, class).
#pragma once

#include <cstddef>
#include <optional>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/metric/label_fusion.hpp"
#include "engine/metric/occupancy_model.hpp"
#include "engine/metric/semantic_blocks.hpp"
#include "engine/metric/semantic_voxel.hpp"
#include "engine/metric/voxel_key.hpp"

namespace sarmap::metric {

struct MetricMapSettings {
  double resolution = 0.05;  // voxel edge in metres, in [0.01, 100]
  OccupancySettings occupancy;
  LabelFusionSettings fusion;
};

// Default settings at another voxel size.
inline MetricMapSettings settings_at_resolution(double resolution) {
  MetricMapSettings settings;
  settings.resolution = resolution;
  return settings;
}

struct MapCounts {
  std::size_t blocks = 0, known = 0, free = 0, occupied = 0;
};

class MetricMap {
 public:
  using Blocks = SemanticBlocks;

  // Throws sarmap::Error (InvalidArgument) for settings out of range.
  explicit MetricMap(const MetricMapSettings& settings = {});

  const MetricMapSettings& settings() const { return settings_; }
  double resolution() const { return settings_.resolution; }
  double inv_resolution() const { return inv_resolution_; }
  const OccupancyModel& occupancy() const { return occupancy_; }
  const LabelFusion& fusion() const { return fusion_; }
  Blocks& blocks() { return blocks_; }
  const Blocks& blocks() const { return blocks_; }

  // Voxel holding a point; nullopt beyond +-10 km (or NaN).
  std::optional<VoxelKey> key_at(const Eigen::Vector3d& point) const;
  Eigen::Vector3d center_of(const VoxelKey& key) const;

  VoxelState state(const VoxelKey& key) const;
  // Unknown beyond the map limits.
  VoxelState state_at(const Eigen::Vector3d& point) const;
  // Occupancy probability; 0.5 for unknown voxels.
  double probability_at(const Eigen::Vector3d& point) const;
  // Dominant class of an occupied voxel; Unknown for free and unknown voxels.
  ClassId class_of(const VoxelKey& key) const;
  ClassId class_at(const Eigen::Vector3d& point) const;
  // Class evidence of a voxel (zeros if unknown).
  ClassEvidence evidence(const VoxelKey& key) const;
  // Replaces a known voxel's class evidence with what one observation says
  // (its classes decided elsewhere, e.g. by the classifier of the
  // accumulated map); false, and nothing changed, for a voxel not known.
  bool replace_evidence(const VoxelKey& key, const ClassObservation& observation);

  // Counts every voxel; costs a pass over all blocks.
  MapCounts counts() const;
  // Bytes the map allocates, counted by its blocks (SemanticBlocks::
  // memory_bytes: block records and their key index, log-odds slabs,
  // evidence rows) plus the map object itself; not the ray integrator's
  // scratch (RayIntegrator::scratch_bytes).
  std::size_t memory_bytes() const { return sizeof(*this) - sizeof(Blocks) + blocks_.memory_bytes(); }

  // Every block, for a checkpoint (engine/core/state_stream.hpp).
  void save_state(StateWriter& out) const;
  // Replaces the blocks with saved ones. Throws sarmap::Error (Parse) naming
  // the offset for a stream that holds no map of this resolution and fusion,
  // or a block key out of the map's reach; the map is unchanged then.
  void load_state(StateReader& in);

 private:
  MetricMapSettings settings_;
  double inv_resolution_;
  OccupancyModel occupancy_;
  LabelFusion fusion_;
  Blocks blocks_;
};

}  // namespace sarmap::metric
