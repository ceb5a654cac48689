// Points as a structure of arrays: x, y, z and each optional attribute live in
// their own 64-byte-aligned array, so kernels stream contiguous floats and no
// per-point object exists on a hot path.
//
// Coordinates are float32: within about 10 km of the map origin that keeps
// about 1 mm of precision, which is below any voxel size sarmap uses. Data
// georeferenced far from the origin must be shifted before it gets here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "engine/core/aligned_vector.hpp"
#include "engine/core/bounds.hpp"
#include "engine/core/state_stream.hpp"

namespace sarmap {

class PointBuffer {
 public:
  PointBuffer() = default;
  explicit PointBuffer(std::size_t count) { resize(count); }

  std::size_t size() const { return x_.size(); }
  bool empty() const { return x_.empty(); }

  // Resizes coordinates and every enabled attribute; new entries are zero.
  void resize(std::size_t count);
  void reserve(std::size_t count);
  // Removes all points; enabled attributes stay enabled.
  void clear() { resize(0); }
  // Appends one point; its enabled attributes are zero until set.
  void push_back(float x, float y, float z);

  std::span<float> x() { return x_; }
  std::span<float> y() { return y_; }
  std::span<float> z() { return z_; }
  std::span<const float> x() const { return x_; }
  std::span<const float> y() const { return y_; }
  std::span<const float> z() const { return z_; }

  // --- optional attributes; enable_* allocates the array zero-filled ---
  // Class id per point (ClassId values): input labels or sarmap's prediction.
  bool has_labels() const { return has_labels_; }
  void enable_labels();
  std::span<std::uint8_t> labels() { return labels_; }
  std::span<const std::uint8_t> labels() const { return labels_; }

  // Ground-truth class id kept beside a prediction (PLY property gt_label).
  bool has_gt_labels() const { return has_gt_labels_; }
  void enable_gt_labels();
  std::span<std::uint8_t> gt_labels() { return gt_labels_; }
  std::span<const std::uint8_t> gt_labels() const { return gt_labels_; }

  // Colour, one byte array per channel.
  bool has_colors() const { return has_colors_; }
  void enable_colors();
  std::span<std::uint8_t> red() { return red_; }
  std::span<std::uint8_t> green() { return green_; }
  std::span<std::uint8_t> blue() { return blue_; }
  std::span<const std::uint8_t> red() const { return red_; }
  std::span<const std::uint8_t> green() const { return green_; }
  std::span<const std::uint8_t> blue() const { return blue_; }

  bool has_intensity() const { return has_intensity_; }
  void enable_intensity();
  std::span<float> intensity() { return intensity_; }
  std::span<const float> intensity() const { return intensity_; }

  bool has_normals() const { return has_normals_; }
  void enable_normals();
  std::span<float> normal_x() { return nx_; }
  std::span<float> normal_y() { return ny_; }
  std::span<float> normal_z() { return nz_; }
  std::span<const float> normal_x() const { return nx_; }
  std::span<const float> normal_y() const { return ny_; }
  std::span<const float> normal_z() const { return nz_; }

  // Named per-point scalar channels, one array each (per-class scores are
  // named after the class: PLY writes them as scalar_<name>).
  std::size_t score_count() const { return score_names_.size(); }
  const std::vector<std::string>& score_names() const { return score_names_; }
  // Adds a zero-filled channel and returns its index; an existing name is reused.
  std::size_t add_score(const std::string& name);
  // Index of a channel, or score_count() when absent.
  std::size_t find_score(const std::string& name) const;
  std::span<float> score(std::size_t channel) { return scores_[channel]; }
  std::span<const float> score(std::size_t channel) const { return scores_[channel]; }

  // Appends every point of other; attributes present on either side are
  // enabled on the result (zero where a side lacked them).
  void append(const PointBuffer& other);
  // The points at the given indices, with all attributes, in that order.
  PointBuffer select(std::span<const std::uint32_t> indices) const;
  // Drops points whose x, y or z is NaN or infinite; returns how many.
  std::size_t remove_non_finite();
  // Drops points farther than `distance` from `centre` (NaN ones too); returns how many.
  std::size_t remove_farther_than(const Eigen::Vector3d& centre, double distance);
  // Bounds of the coordinates (empty for an empty buffer).
  Bounds bounds() const;
  // Bytes its arrays hold, by capacity (engine/core/capacity_bytes.hpp).
  std::size_t memory_bytes() const;
  // Copies the set of enabled attributes (not their values) from other.
  void enable_attributes_of(const PointBuffer& other);

  // Every point and attribute, for a checkpoint (state_stream.hpp).
  void save_state(StateWriter& out) const;
  // Replaces the points with saved ones. Throws sarmap::Error (Parse) naming
  // the offset; unchanged then.
  void load_state(StateReader& in);

 private:
  // Compacts every array in place, keeping point i where keeps(i); returns
  // how many went. Counts first, so that when none goes (most scans)
  // nothing is allocated or moved. Defined in point_buffer.cpp, its only user.
  template <class Keeps>
  std::size_t keep_where(Keeps keeps);

  AlignedVector<float> x_, y_, z_;
  bool has_labels_ = false, has_gt_labels_ = false, has_colors_ = false;
  bool has_intensity_ = false, has_normals_ = false;
  AlignedVector<std::uint8_t> labels_, gt_labels_, red_, green_, blue_;
  AlignedVector<float> intensity_, nx_, ny_, nz_;
  std::vector<std::string> score_names_;
  std::vector<AlignedVector<float>> scores_;

  // Calls fn on each enabled attribute's array of `self` (a PointBuffer,
  // const or not): the one list of the arrays.
  template <class Self, class Fn>
  static void for_each_array(Self& self, Fn&& fn);
};

}  // namespace sarmap
