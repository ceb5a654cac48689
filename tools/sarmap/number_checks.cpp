#include "tools/sarmap/number_checks.hpp"

#include <cmath>
#include <cstdlib>
#include <string>

namespace sarmap::cli {
namespace {

// Empty when `text` is a finite number above (or, with allow_zero, at) zero; else why not.
std::string check_number(const std::string& text, bool allow_zero) {
  const char* start = text.c_str();
  char* end = nullptr;
  const double value = std::strtod(start, &end);
  const std::string wanted = allow_zero ? "a finite number >= 0" : "a finite number > 0";
  if (end == start || *end != '\0' || !std::isfinite(value) || value < 0 || (!allow_zero && value == 0)) {
    return "must be " + wanted + ", got '" + text + "'";
  }
  return {};
}

}  // namespace

const CLI::Validator& finite_non_negative() {
  static const CLI::Validator check([](std::string& text) { return check_number(text, true); }, "NUMBER>=0");
  return check;
}

std::optional<std::vector<double>> finite_number_list(const std::string& text, std::size_t count) {
  std::vector<double> values;
  std::size_t start = 0;
  while (values.size() < count) {
    const std::size_t comma = text.find(',', start);
    const bool last = values.size() + 1 == count;
    if (last != (comma == std::string::npos)) return std::nullopt;  // too few or too many
    const std::string part = text.substr(start, last ? std::string::npos : comma - start);
    char* end = nullptr;
    const double value = std::strtod(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size() || !std::isfinite(value)) return std::nullopt;
    values.push_back(value);
    start = comma + 1;
  }
  return values;
}

const CLI::Validator& finite_positive() {
  static const CLI::Validator check([](std::string& text) { return check_number(text, false); }, "NUMBER>0");
  return check;
}

}  // namespace sarmap::cli
