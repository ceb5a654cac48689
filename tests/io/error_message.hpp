// Runs a callable that must throw sarmap::Error and returns the message, so
// tests can check that an error names the file, line and field.
#pragma once

#include <gtest/gtest.h>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::test {

template <class Fn>
std::string error_message(Fn&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a sarmap::Error";
  return {};
}

}  // namespace sarmap::test
