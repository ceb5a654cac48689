// A score that may be undefined (no samples) as JSON: the number, or null.
#pragma once

#include <optional>

#include <nlohmann/json.hpp>

namespace sarmap::eval {

inline nlohmann::ordered_json optional_json_number(const std::optional<double>& v) {
  return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr);
}

}  // namespace sarmap::eval
