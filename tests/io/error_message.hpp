// Runs a callable that must throw sarmap::Error and returns the message, or
// checks its code and a fragment of it, so tests can check that an error
// names the file, line and field.
#pragma once

#include <gtest/gtest.h>
#include <string>
#include <utility>

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

// Expects fn to throw sarmap::Error with this code, its message holding `fragment`.
template <class Fn>
void expect_error(Fn&& fn, ErrorCode code, const std::string& fragment) {
  try {
    fn();
    ADD_FAILURE() << "no error; expected one naming '" << fragment << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code);
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

template <class Fn>
void expect_invalid_argument(Fn&& fn, const std::string& fragment) {
  expect_error(std::forward<Fn>(fn), ErrorCode::InvalidArgument, fragment);
}

}  // namespace sarmap::test
