// The parts of the _sarmap extension, one per file, each adding its classes
// and functions to the module (module.cpp calls them in order).
#pragma once

#include <pybind11/pybind11.h>

namespace sarmap::python {

namespace py = pybind11;

void bind_errors(py::module_& m);    // errors.cpp
void bind_cloud(py::module_& m);     // cloud_bindings.cpp: PointCloud, read_cloud, write_cloud
void bind_sequence(py::module_& m);  // sequence_bindings.cpp: open_sequence
void bind_mapper(py::module_& m);    // mapper_bindings.cpp: Mapper
void bind_classify(py::module_& m);  // classify_bindings.cpp: classify
void bind_threads(py::module_& m);   // thread_bindings.cpp: set_threads, threads

}  // namespace sarmap::python
