// How the library's errors reach Python: sarmap::Error becomes OSError for a
// file that could not be read or written and ValueError for everything else
// (bad values, malformed files), with the library's message, which already
// names the file, offset or key.
#pragma once

#include <string>

#include <pybind11/pybind11.h>

namespace sarmap::python {

// A wrong type for argument `name`: TypeError "name: what".
[[noreturn]] void type_error(const char* name, const std::string& what);
// A wrong value (shape, range, NaN) for argument `name`: ValueError "name: what".
[[noreturn]] void value_error(const char* name, const std::string& what);

}  // namespace sarmap::python
