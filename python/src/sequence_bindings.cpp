// open_sequence: a scan sequence (sarmap folder, TUM RGB-D, 7-Scenes, one
// PLY/PCD file) read one frame at a time through engine/io's ScanSource,
// each frame's points handed over as a PointCloud without a copy.
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "engine/io/scan_source.hpp"
#include "python/src/array_arguments.hpp"
#include "python/src/bindings.hpp"
#include "python/src/config_arguments.hpp"
#include "python/src/sequence.hpp"

namespace sarmap::python {

Sequence::Sequence(std::string path, const ScanSequenceOptions& options)
    : path_(std::move(path)), source_(open_scan_sequence(path_, options)) {}

bool Sequence::next(Scan& scan) {
  std::lock_guard lock(mutex_);
  return source_->next(scan);
}

void Sequence::rewind() {
  std::lock_guard lock(mutex_);
  source_->rewind();
}

void Sequence::skip_to(std::size_t frame) {
  std::lock_guard lock(mutex_);
  source_->skip_to(frame);
}

namespace {

py::object scan_object(Scan&& scan) {
  const Eigen::Matrix4d m = scan.pose.matrix();
  py::array_t<double> pose({4, 4});
  auto rows = pose.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) rows(r, c) = m(r, c);
  }
  py::array_t<double> origin(3);
  for (int i = 0; i < 3; ++i) origin.mutable_at(i) = scan.origin[i];
  return py::module_::import("sarmap._scan")
      .attr("Scan")(py::cast(std::move(scan.points)), pose, origin, scan.index, scan.source, scan.timestamp,
                    scan.dropped_non_finite);
}

}  // namespace

void bind_sequence(py::module_& m) {
  py::class_<Sequence>(m, "Sequence", R"doc(
A scan sequence opened by open_sequence(). Iterating it reads one frame at a
time from the first: each item unpacks as (points, pose, origin), points a
PointCloud in the world frame (the frame's file's fields, labels included),
pose the (4, 4) sensor-to-world matrix, origin the (3,) ray origin; it also
has index, source, timestamp and dropped_non_finite. A frame that cannot be
read raises OSError or ValueError naming its file; the sequence has moved past
it, so next() goes on with the following frame.)doc")
      .def("__len__", [](const Sequence& s) { return s.source().size(); })
      .def(
          "__iter__",
          [](Sequence& s) -> Sequence& {
            s.rewind();
            return s;
          },
          py::return_value_policy::reference_internal)
      .def("__next__",
           [](Sequence& s) {
             Scan scan;
             bool more = false;
             {
               py::gil_scoped_release release;
               more = s.next(scan);
             }
             if (!more) throw py::stop_iteration();
             return scan_object(std::move(scan));
           })
      .def_property_readonly("path", &Sequence::path)
      .def_property_readonly(
          "layout", [](const Sequence& s) { return s.source().layout(); },
          "\"sarmap\", \"tum\", \"7scenes\" or \"cloud\"")
      .def_property_readonly(
          "sensor", [](const Sequence& s) { return sensor_dict(s.source().sensor()); },
          "the sensor as a dict (Mapper's sensor argument)")
      .def_property_readonly(
          "arena_sha256", [](const Sequence& s) { return s.source().arena_sha256(); },
          "the SHA-256 of the arena a simulated sequence came from, or \"\"")
      .def("__repr__", [](const Sequence& s) {
        return "Sequence(" + s.path() + ", " + s.source().layout() + ", " +
               std::to_string(s.source().size()) + " frames)";
      });

  m.def(
      "open_sequence",
      [](const py::object& path, const py::object& intrinsics, double max_depth, double max_time_difference) {
        ScanSequenceOptions options;
        if (!intrinsics.is_none()) options.intrinsics_file = path_argument(intrinsics, "intrinsics");
        options.max_depth = max_depth;
        options.max_time_difference = max_time_difference;
        const std::string folder = path_argument(path);
        py::gil_scoped_release release;
        return std::make_unique<Sequence>(folder, options);
      },
      py::arg("path"), py::kw_only(), py::arg("intrinsics") = py::none(), py::arg("max_depth") = 0.0,
      py::arg("max_time_difference") = 0.02,
      "Opens a sarmap sequence folder (sequence.json), a TUM RGB-D or 7-Scenes folder, or one PLY/PCD file "
      "as a "
      "one-frame sequence. intrinsics: a pinhole intrinsics file for depth images; max_depth: drop deeper "
      "depth "
      "values (0 keeps all); max_time_difference: TUM's pose-to-frame time tolerance (s).");
}

}  // namespace sarmap::python
