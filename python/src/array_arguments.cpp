#include "python/src/array_arguments.hpp"

#include <string>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "python/src/errors.hpp"

namespace sarmap::python {

namespace {

std::string shape_text(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_text(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

using RealArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A real (bool, integer or floating) numpy array made from any array-like, as float64.
RealArray real_array(const py::handle& value, const char* name) {
  if (py::isinstance<py::array>(value)) {
    const char kind = py::reinterpret_borrow<py::array>(value).dtype().kind();
    if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f') {
      type_error(name, "expected real numbers, got a " + describe(value));
    }
  }
  // ensure() converts (a copy for anything but a C-ordered float64 array) and
  // gives a null array, the Python error cleared, for what does not convert.
  auto result = RealArray::ensure(value);
  if (!result) type_error(name, "expected an array of real numbers, got a " + describe(value));
  return result;
}

[[noreturn]] void bad_class_id(const char* name, std::size_t point, unsigned id) {
  value_error(name, "point " + std::to_string(point) + " has class " + std::to_string(id) +
                        ", not a class id (0.." + std::to_string(kClassCount - 1) + ")");
}

}  // namespace

std::string describe(const py::handle& value) {
  if (py::isinstance<py::array>(value)) {
    const auto a = py::reinterpret_borrow<py::array>(value);
    return dtype_text(a) + " array of shape " + shape_text(a);
  }
  return py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>();
}

std::string path_argument(const py::handle& value, const char* name) {
  if (!py::isinstance<py::str>(value) && !py::hasattr(value, "__fspath__")) {
    type_error(name, "expected a str or os.PathLike, got a " + describe(value));
  }
  const py::object path = py::module_::import("os").attr("fspath")(value);
  if (!py::isinstance<py::str>(path)) type_error(name, "expected a str path, got bytes");
  return path.cast<std::string>();
}

py::array_t<float> float32_points(const py::handle& value, const char* name) {
  if (!py::isinstance<py::array_t<float>>(value)) {
    type_error(name, "expected an (N, 3) float32 array, got a " + describe(value) +
                         " (convert with numpy.asarray(points, dtype=numpy.float32))");
  }
  auto a = py::reinterpret_borrow<py::array_t<float>>(value);
  if (a.ndim() != 2 || a.shape(1) != 3) value_error(name, "expected shape (N, 3), got " + shape_text(a));
  return a;
}

void check_class_ids(std::span<const std::uint8_t> ids, const char* name) {
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] >= kClassCount) bad_class_id(name, i, ids[i]);
  }
}

py::array_t<std::uint8_t> class_ids(const py::handle& value, const char* name, std::size_t count) {
  if (!py::isinstance<py::array_t<std::uint8_t>>(value)) {
    type_error(name, "expected an (N,) uint8 array of class ids, got a " + describe(value) +
                         " (convert with numpy.asarray(labels, dtype=numpy.uint8))");
  }
  auto a = py::reinterpret_borrow<py::array_t<std::uint8_t>>(value);
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != count) {
    value_error(name,
                "expected shape (" + std::to_string(count) + ",) to match the points, got " + shape_text(a));
  }
  const auto ids = a.unchecked<1>();  // any strides
  for (py::ssize_t i = 0; i < ids.shape(0); ++i) {
    if (ids(i) >= kClassCount) bad_class_id(name, static_cast<std::size_t>(i), ids(i));
  }
  return a;
}

Pose pose_argument(const py::handle& value, const char* name) {
  const RealArray a = real_array(value, name);
  if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) {
    value_error(name, "expected a (4, 4) matrix, got shape " + shape_text(a));
  }
  const auto m = a.unchecked<2>();
  Eigen::Matrix4d matrix;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) matrix(r, c) = m(r, c);
  }
  try {
    return Pose::from_matrix(matrix, name);  // its messages start with `name`
  } catch (const Error& e) {
    throw py::value_error(e.what());
  }
}

Eigen::Vector3d point_argument(const py::handle& value, const char* name) {
  const RealArray a = real_array(value, name);
  if (a.ndim() != 1 || a.shape(0) != 3)
    value_error(name, "expected 3 coordinates, got shape " + shape_text(a));
  const Eigen::Vector3d p(a.at(0), a.at(1), a.at(2));
  if (!p.allFinite()) value_error(name, "coordinates must be finite");
  return p;
}

PointBuffer point_buffer_argument(const py::handle& points, const py::handle& labels, const char* name) {
  PointBuffer buffer;
  if (py::isinstance<PointBuffer>(points)) {
    buffer = points.cast<const PointBuffer&>();
    if (labels.is_none() && buffer.has_labels()) {
      // A cloud's labels are writable views: check them as an argument's.
      check_class_ids(buffer.labels(), name);
    }
  } else {
    const py::array_t<float> array = float32_points(points, name);
    const auto rows = array.unchecked<2>();
    buffer.resize(static_cast<std::size_t>(rows.shape(0)));
    for (py::ssize_t i = 0; i < rows.shape(0); ++i) {
      const auto p = static_cast<std::size_t>(i);
      buffer.x()[p] = rows(i, 0);
      buffer.y()[p] = rows(i, 1);
      buffer.z()[p] = rows(i, 2);
    }
  }
  if (!labels.is_none()) {
    const py::array_t<std::uint8_t> array = class_ids(labels, "labels", buffer.size());
    const auto ids = array.unchecked<1>();
    buffer.enable_labels();
    for (py::ssize_t i = 0; i < ids.shape(0); ++i) buffer.labels()[static_cast<std::size_t>(i)] = ids(i);
  }
  return buffer;
}

QueryPoints::QueryPoints(const py::handle& value, const char* name) {
  py::array a;
  if (py::isinstance<py::array_t<double>>(value) || py::isinstance<py::array_t<float>>(value)) {
    a = py::reinterpret_borrow<py::array>(value);
  } else if (py::isinstance<py::array>(value)) {
    type_error(name, "expected a float32 or float64 array of points, got a " + describe(value));
  } else {
    a = real_array(value, name);
  }
  if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 3) {
    value_error(name, "expected points of shape (..., 3), got " + shape_text(a));
  }
  shape_.assign(a.shape(), a.shape() + a.ndim() - 1);
  // A view whenever numpy can express the rows with strides (always for
  // (N, 3) and for contiguous inputs).
  array_ = a.attr("reshape")(-1, 3).cast<py::array>();
  is_double_ = py::isinstance<py::array_t<double>>(array_);
  data_ = static_cast<const char*>(array_.data());
  count_ = static_cast<std::size_t>(array_.shape(0));
  row_stride_ = array_.strides(0);
  column_stride_ = array_.strides(1);
}

py::capsule owner_of(PointBuffer&& points) {
  return py::capsule(new PointBuffer(std::move(points)),
                     [](void* p) { delete static_cast<PointBuffer*>(p); });
}

}  // namespace sarmap::python
