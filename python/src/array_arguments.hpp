// numpy arguments checked by name before any engine call (a wrong dtype is a
// TypeError, a wrong shape or value a ValueError, never a crash), and numpy
// views over engine buffers that keep their owner alive. What crosses with
// and without a copy is listed in docs/python.md ("Copies").
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <Eigen/Core>

#include "engine/core/point_buffer.hpp"
#include "engine/core/pose.hpp"

namespace sarmap::python {

namespace py = pybind11;

// An (N, 3) float32 array, any strides, used in place. TypeError naming
// `name` for a non-array or another dtype (no silent float64 -> float32),
// ValueError for another shape.
py::array_t<float> float32_points(const py::handle& value, const char* name);

// An (N,) uint8 array of class ids (each < kClassCount), N = `count`.
py::array_t<std::uint8_t> class_ids(const py::handle& value, const char* name, std::size_t count);

// ValueError naming `name` and the first point whose id is kClassCount or more.
void check_class_ids(std::span<const std::uint8_t> ids, const char* name);

// A (4, 4) rigid sensor-to-world transform: any real array-like; ValueError
// for another shape, NaN, a last row other than [0 0 0 1] or a rotation that
// is not orthonormal with determinant +1 (core/pose.hpp's tolerance).
Pose pose_argument(const py::handle& value, const char* name);

// A finite (3,) point.
Eigen::Vector3d point_argument(const py::handle& value, const char* name);

// `points` (an (N, 3) float32 array or a PointCloud) as an engine buffer: a
// copy, since the engine filters and labels its points in place. `labels`
// (None or (N,) uint8) replaces the cloud's labels. Class ids are checked.
PointBuffer point_buffer_argument(const py::handle& points, const py::handle& labels, const char* name);

// Points to query: an (..., 3) float32 or float64 array read in place with
// any strides, or a list numpy turns into float64 (that conversion is a
// copy). Reading a point needs no GIL; `array` keeps the memory alive.
class QueryPoints {
 public:
  QueryPoints(const py::handle& value, const char* name);

  std::size_t size() const { return count_; }
  // The result's shape: the input's without its last axis.
  const std::vector<py::ssize_t>& result_shape() const { return shape_; }
  Eigen::Vector3d operator[](std::size_t i) const {
    const char* row = data_ + static_cast<py::ssize_t>(i) * row_stride_;
    return is_double_ ? Eigen::Vector3d(at<double>(row, 0), at<double>(row, 1), at<double>(row, 2))
                      : Eigen::Vector3d(at<float>(row, 0), at<float>(row, 1), at<float>(row, 2));
  }

 private:
  // memcpy: numpy allows unaligned arrays.
  template <class T>
  T at(const char* row, py::ssize_t column) const {
    T value;
    std::memcpy(&value, row + column * column_stride_, sizeof(T));
    return value;
  }

  py::array array_;
  const char* data_ = nullptr;
  py::ssize_t row_stride_ = 0, column_stride_ = 0;
  std::size_t count_ = 0;
  bool is_double_ = true;
  std::vector<py::ssize_t> shape_;
};

// A 1-D numpy view of `values` (no copy) whose base is `owner`: the memory
// lives as long as the owner, which the view keeps alive.
template <class T>
py::array_t<T> view_of(std::span<T> values, const py::handle& owner) {
  return py::array_t<T>({static_cast<py::ssize_t>(values.size())}, {static_cast<py::ssize_t>(sizeof(T))},
                        values.data(), owner);
}

// Moves a buffer into a Python object that owns it, for views of a result
// (a classification's labels) that no PointCloud holds.
py::capsule owner_of(PointBuffer&& points);

// Three coordinate arrays as one (N, 3) array: always a copy (the engine keeps
// x, y and z apart).
template <class T>
py::array_t<T> interleave(std::span<const T> a, std::span<const T> b, std::span<const T> c) {
  py::array_t<T> out({static_cast<py::ssize_t>(a.size()), py::ssize_t{3}});
  auto rows = out.template mutable_unchecked<2>();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto r = static_cast<py::ssize_t>(i);
    rows(r, 0) = a[i];
    rows(r, 1) = b[i];
    rows(r, 2) = c[i];
  }
  return out;
}

// A str or os.PathLike as a path string; TypeError otherwise.
std::string path_argument(const py::handle& value, const char* name = "path");

// The dtype and shape of an object for messages: "float64 array of shape (5, 2)", "list".
std::string describe(const py::handle& value);

}  // namespace sarmap::python
