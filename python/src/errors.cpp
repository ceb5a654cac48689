#include "python/src/errors.hpp"

#include "engine/core/error.hpp"
#include "python/src/bindings.hpp"

namespace sarmap::python {

void type_error(const char* name, const std::string& what) {
  throw py::type_error(std::string(name) + ": " + what);
}

void value_error(const char* name, const std::string& what) {
  throw py::value_error(std::string(name) + ": " + what);
}

void bind_errors(py::module_& m) {
  (void)m;
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const Error& e) {
      PyErr_SetString(e.code() == ErrorCode::Io ? PyExc_OSError : PyExc_ValueError, e.what());
    }
  });
}

}  // namespace sarmap::python
