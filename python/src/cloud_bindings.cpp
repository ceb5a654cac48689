// PointCloud (the engine's PointBuffer, whose arrays numpy views without a
// copy), read_cloud and write_cloud (PLY / PCD through engine/io).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>

#include <pybind11/stl.h>

#include "engine/io/point_cloud_file.hpp"
#include "python/src/array_arguments.hpp"
#include "python/src/bindings.hpp"
#include "python/src/errors.hpp"

namespace sarmap::python {

namespace {

// An optional (N,) array of `T` beside N points, copied into `into` (made by `enable`).
template <class T>
void copy_column(const py::handle& value, const char* name, std::size_t count, std::span<T> into) {
  if (!py::isinstance<py::array_t<T>>(value)) {
    type_error(name, std::string("expected an (N,) ") + py::str(py::dtype::of<T>()).cast<std::string>() +
                         " array, got a " + describe(value));
  }
  const auto a = py::reinterpret_borrow<py::array_t<T>>(value);
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != count) {
    value_error(
        name, "expected shape (" + std::to_string(count) + ",) to match the points, got " + describe(value));
  }
  const auto v = a.template unchecked<1>();
  for (py::ssize_t i = 0; i < v.shape(0); ++i) into[static_cast<std::size_t>(i)] = v(i);
}

// A cloud from arrays: points (N, 3) float32 and the optional columns.
PointBuffer cloud_from_arrays(const py::handle& points, const py::handle& labels, const py::handle& colors,
                              const py::handle& intensity, const py::handle& scores) {
  PointBuffer cloud = point_buffer_argument(points, labels, "points");
  const std::size_t n = cloud.size();
  if (!colors.is_none()) {
    if (!py::isinstance<py::array_t<std::uint8_t>>(colors)) {
      type_error("colors", "expected an (N, 3) uint8 array, got a " + describe(colors));
    }
    const auto a = py::reinterpret_borrow<py::array_t<std::uint8_t>>(colors);
    if (a.ndim() != 2 || a.shape(1) != 3 || static_cast<std::size_t>(a.shape(0)) != n) {
      value_error("colors", "expected shape (" + std::to_string(n) + ", 3), got " + describe(colors));
    }
    const auto rgb = a.unchecked<2>();
    cloud.enable_colors();
    for (py::ssize_t i = 0; i < rgb.shape(0); ++i) {
      const auto p = static_cast<std::size_t>(i);
      cloud.red()[p] = rgb(i, 0);
      cloud.green()[p] = rgb(i, 1);
      cloud.blue()[p] = rgb(i, 2);
    }
  }
  if (!intensity.is_none()) {
    cloud.enable_intensity();
    copy_column<float>(intensity, "intensity", n, cloud.intensity());
  }
  if (!scores.is_none()) {
    if (!py::isinstance<py::dict>(scores))
      type_error("scores", "expected a dict of name: (N,) float32 array");
    for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(scores)) {
      if (!py::isinstance<py::str>(key)) type_error("scores", "its keys must be channel names (str)");
      const std::string name = "scores[\"" + key.cast<std::string>() + "\"]";
      copy_column<float>(value, name.c_str(), n, cloud.score(cloud.add_score(key.cast<std::string>())));
    }
  }
  return cloud;
}

template <class T>
py::object optional_view(bool present, std::span<T> values, const py::handle& owner) {
  return present ? py::object(view_of(values, owner)) : py::object(py::none());
}

PointBuffer& cloud_of(const py::object& self) { return self.cast<PointBuffer&>(); }

}  // namespace

void bind_cloud(py::module_& m) {
  py::class_<PointBuffer>(m, "PointCloud", R"doc(
Points as the engine holds them: x, y, z and each optional field in an array of
its own. The array properties are numpy views of the cloud's memory (no copy;
writable; each keeps the cloud alive); xyz, colors and numpy.asarray(cloud)
gather the separate arrays into one (N, 3) array, which is a copy.)doc")
      .def(py::init([](const py::object& points, const py::object& labels, const py::object& colors,
                       const py::object& intensity, const py::object& scores) {
             return cloud_from_arrays(points, labels, colors, intensity, scores);
           }),
           py::arg("points"), py::kw_only(), py::arg("labels") = py::none(), py::arg("colors") = py::none(),
           py::arg("intensity") = py::none(), py::arg("scores") = py::none(),
           "A cloud from an (N, 3) float32 array and optional (N,) uint8 labels, (N, 3) uint8 colors, (N,) "
           "float32 "
           "intensity and a dict of (N,) float32 score channels (all copied).")
      .def("__len__", [](const PointBuffer& c) { return c.size(); })
      .def("__repr__",
           [](const PointBuffer& c) {
             std::string fields = "x, y, z";
             if (c.has_labels()) fields += ", labels";
             if (c.has_gt_labels()) fields += ", gt_labels";
             if (c.has_colors()) fields += ", colors";
             if (c.has_intensity()) fields += ", intensity";
             if (c.has_normals()) fields += ", normals";
             for (const std::string& s : c.score_names()) fields += ", " + s;
             return "PointCloud(" + std::to_string(c.size()) + " points: " + fields + ")";
           })
      .def(
          "__array__",
          [](const PointBuffer& c, const py::object& dtype) {
            py::object xyz = interleave<float>(c.x(), c.y(), c.z());
            return dtype.is_none() ? xyz : xyz.attr("astype")(dtype);
          },
          py::arg("dtype") = py::none())
      .def_property_readonly(
          "x", [](const py::object& self) { return view_of(cloud_of(self).x(), self); }, "(N,) float32 view")
      .def_property_readonly(
          "y", [](const py::object& self) { return view_of(cloud_of(self).y(), self); }, "(N,) float32 view")
      .def_property_readonly(
          "z", [](const py::object& self) { return view_of(cloud_of(self).z(), self); }, "(N,) float32 view")
      .def_property_readonly(
          "xyz", [](const PointBuffer& c) { return interleave<float>(c.x(), c.y(), c.z()); },
          "(N, 3) float32 copy of x, y, z")
      .def_property_readonly(
          "labels",
          [](const py::object& self) {
            PointBuffer& c = cloud_of(self);
            return optional_view(c.has_labels(), c.labels(), self);
          },
          "(N,) uint8 class ids (view), or None")
      .def_property_readonly(
          "gt_labels",
          [](const py::object& self) {
            PointBuffer& c = cloud_of(self);
            return optional_view(c.has_gt_labels(), c.gt_labels(), self);
          },
          "(N,) uint8 ground-truth class ids (view), or None")
      .def_property_readonly(
          "intensity",
          [](const py::object& self) {
            PointBuffer& c = cloud_of(self);
            return optional_view(c.has_intensity(), c.intensity(), self);
          },
          "(N,) float32 (view), or None")
      .def_property_readonly(
          "colors",
          [](const PointBuffer& c) -> py::object {
            if (!c.has_colors()) return py::none();
            return interleave<std::uint8_t>(c.red(), c.green(), c.blue());
          },
          "(N, 3) uint8 copy of the red, green and blue arrays, or None")
      .def_property_readonly(
          "scores",
          [](const py::object& self) {
            PointBuffer& c = cloud_of(self);
            py::dict scores;
            for (std::size_t s = 0; s < c.score_count(); ++s)
              scores[py::str(c.score_names()[s])] = view_of(c.score(s), self);
            return scores;
          },
          "the named float32 channels (per-class scores, probability, ...) as (N,) views");

  m.def(
      "read_cloud",
      [](const py::object& path) {
        const std::string file = path_argument(path);
        PointBuffer cloud;
        {
          py::gil_scoped_release release;
          cloud = read_point_cloud(file);
        }
        return cloud;
      },
      py::arg("path"),
      "Reads a PLY or PCD file (by extension) into a PointCloud; points with a NaN or infinite coordinate "
      "are "
      "dropped, as every sarmap reader does.");

  m.def(
      "write_cloud",
      [](const py::object& path, const py::object& points, const py::object& labels, const py::object& colors,
         const py::object& intensity, const py::object& scores, bool binary, bool compressed) {
        const std::string file = path_argument(path);
        PointCloudWriteOptions options;
        options.binary = binary;
        options.compressed = compressed;
        const bool is_cloud = py::isinstance<PointBuffer>(points);
        if (is_cloud && !(labels.is_none() && colors.is_none() && intensity.is_none() && scores.is_none())) {
          type_error("points",
                     "a PointCloud carries its own fields: give labels, colors, intensity or scores "
                     "with an array of points");
        }
        // A PointCloud is written from its own memory; arrays are gathered into one first.
        if (is_cloud) {
          const PointBuffer& cloud = points.cast<const PointBuffer&>();
          py::gil_scoped_release release;
          write_point_cloud(file, cloud, options);
          return;
        }
        const PointBuffer cloud = cloud_from_arrays(points, labels, colors, intensity, scores);
        py::gil_scoped_release release;
        write_point_cloud(file, cloud, options);
      },
      py::arg("path"), py::arg("points"), py::kw_only(), py::arg("labels") = py::none(),
      py::arg("colors") = py::none(), py::arg("intensity") = py::none(), py::arg("scores") = py::none(),
      py::arg("binary") = true, py::arg("compressed") = false,
      "Writes a PointCloud, or an (N, 3) float32 array with optional fields, as PLY or PCD (by extension), "
      "atomically. compressed: PCD binary_compressed.");
}

}  // namespace sarmap::python
