// The _sarmap extension: sarmap's run API for Python (docs/python.md). The
// package's __init__.py re-exports it with the pure-Python helpers.
#include <string>

#include "engine/core/classes.hpp"
#include "engine/core/version.hpp"
#include "engine/metric/semantic_voxel.hpp"
#include "python/src/bindings.hpp"

PYBIND11_MODULE(_sarmap, m) {
  namespace py = pybind11;
  using namespace sarmap;
  m.doc() = "sarmap: semantic, metric and topological maps of search-and-rescue arenas (native part)";
  m.attr("__version__") = std::string(kVersion);
  // Voxel states as state_at() gives them.
  m.attr("UNKNOWN") = static_cast<int>(metric::VoxelState::Unknown);
  m.attr("FREE") = static_cast<int>(metric::VoxelState::Free);
  m.attr("OCCUPIED") = static_cast<int>(metric::VoxelState::Occupied);
  // Class names indexed by class id, as in every file sarmap writes.
  py::tuple names(kClassCount);
  for (std::size_t i = 0; i < kClassCount; ++i) names[i] = std::string(kClassTable[i].name);
  m.attr("CLASS_NAMES") = names;

  python::bind_errors(m);
  python::bind_cloud(m);
  python::bind_sequence(m);
  python::bind_mapper(m);
  python::bind_classify(m);
  python::bind_threads(m);
}
