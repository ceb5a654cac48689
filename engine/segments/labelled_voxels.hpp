// The segment stage's own thinned copy of the labelled points: one point per
// voxel, its class by majority over every label seen in the voxel, the range
// it was seen from and the segment that owns it. Points live in insertion
// order, so an index names a point for the life of the map.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/core/flat_key_index.hpp"
#include "engine/core/state_stream.hpp"

namespace sarmap::segments {

class LabelledVoxels {
 public:
  static constexpr std::int32_t kNoSegment = -1;
  static constexpr std::uint32_t kNoScan = 0xffffffffu;

  // voxel > 0: one point per voxel of that size; 0: one per millimetre (the
  // input is thinned already). Voxel indices use 21 bits per axis, so points
  // farther than reach() from the origin on any axis have no voxel.
  explicit LabelledVoxels(double voxel);

  double reach() const { return reach_; }
  // The voxel's edge, metres (a millimetre for voxel 0).
  double voxel() const { return 1.0 / inverse_voxel_; }
  std::size_t size() const { return x.size(); }
  // Bytes held: every column, the votes and the key index, by capacity.
  std::size_t memory_bytes() const;

  // The voxel holding p (nullopt beyond reach or for NaN), as a packed key.
  std::optional<std::uint64_t> key_of(const Eigen::Vector3d& p) const;
  // The point of a voxel, or nullopt.
  std::optional<std::uint32_t> find(std::uint64_t key) const;
  // A hint that find(key) follows soon (FlatKeyIndex::prefetch).
  void prefetch(std::uint64_t key) const { index_.prefetch(key); }
  // Adds a point to an empty voxel; returns its index.
  std::uint32_t add(std::uint64_t key, const Eigen::Vector3d& p, ClassId label, float range, std::uint32_t scan);
  // Counts one more label in the voxel; returns the class holding the most
  // votes, the current one on a tie (labels change only on a clear majority).
  ClassId vote(std::uint32_t i, ClassId label);
  // Makes `label` the voxel's class outright (a reclassified region).
  void set_label(std::uint32_t i, ClassId label);

  Eigen::Vector3d position(std::uint32_t i) const { return {x[i], y[i], z[i]}; }

  // Keeps only the points whose flag in `keep` (one per point) is set, in
  // their order, and returns each old index's new one (kDropped for a point
  // let go). Every column and the key index shrink with them.
  static constexpr std::uint32_t kDropped = 0xffffffffu;
  std::vector<std::uint32_t> keep_only(const std::vector<std::uint8_t>& keep);

  // Every column, the votes and the voxel keys in insertion order, for a
  // checkpoint: keys recomputed from the stored positions could fall into a
  // neighbouring voxel.
  void save_state(StateWriter& out) const;
  // Replaces the points with saved ones (same voxel size), or throws
  // sarmap::Error (Parse) and leaves them unchanged. Owners and scans are
  // checked by the caller, which knows the segments and scans.
  void load_state(StateReader& in);

  // Per point, indexed alike.
  std::vector<float> x, y, z;
  std::vector<float> range;           // distance from the sensor when stored (infinity: unknown)
  std::vector<std::uint32_t> scan;    // which scan's origin saw it (kNoScan: none)
  std::vector<std::uint8_t> label;    // ClassId
  std::vector<std::int32_t> owner;    // segment id or kNoSegment
  std::vector<std::uint8_t> pending;  // ClassId of the pending list holding it, 0 for none
  std::vector<std::uint8_t> rounds;   // plane searches it joined without ending in a segment

 private:
  std::vector<std::array<std::uint16_t, kClassCount>> votes_;
  FlatKeyIndex index_;
  double inverse_voxel_;
  double reach_;
};

}  // namespace sarmap::segments
