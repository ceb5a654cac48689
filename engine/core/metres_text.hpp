// A length as error messages print it: "0.025 m", with as many digits as the
// value needs, so two settings that differ never print alike.
#pragma once

#include <cstdio>
#include <string>

namespace sarmap {

inline std::string metres_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g m", value);
  return text;
}

}  // namespace sarmap
