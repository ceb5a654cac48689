// set_threads / threads: how many worker threads sarmap's parallel stages
// (oneTBB) may use in this process, as `sarmap run --threads` sets it.
#include <cstddef>
#include <memory>
#include <string>

#include <tbb/global_control.h>

#include "python/src/array_arguments.hpp"
#include "python/src/bindings.hpp"
#include "python/src/errors.hpp"

namespace sarmap::python {

namespace {

// The process-wide limit; none while every core may be used.
std::unique_ptr<tbb::global_control>& thread_limit() {
  static std::unique_ptr<tbb::global_control> limit;
  return limit;
}

}  // namespace

void bind_threads(py::module_& m) {
  m.def(
      "set_threads",
      [](const py::object& threads) {
        if (!py::isinstance<py::int_>(threads) || py::isinstance<py::bool_>(threads)) {
          type_error("threads", "expected an int, got a " + describe(threads));
        }
        const long n = threads.cast<long>();
        if (n < 0) value_error("threads", "must be >= 0 (0 = all cores), got " + std::to_string(n));
        thread_limit().reset();
        if (n > 0) {
          thread_limit() = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                                 static_cast<std::size_t>(n));
        }
      },
      py::arg("threads"), R"doc(
Limits the worker threads of sarmap's parallel stages in this process (the
ray integrator, the classifiers, the stream's two scans in flight) to threads,
as `sarmap run --threads N` does; 0 lifts the limit (every core). The maps do
not depend on it, only the time.)doc");
  m.def(
      "threads",
      [] { return tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism); },
      "The worker threads sarmap's parallel stages may use now (set_threads, else the cores).");
  // The limit goes before oneTBB's own teardown at exit.
  py::module_::import("atexit").attr("register")(py::cpp_function([] { thread_limit().reset(); }));
}

}  // namespace sarmap::python
