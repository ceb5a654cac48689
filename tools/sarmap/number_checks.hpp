// Checks for the CLI's numeric options, so each bad value is refused naming
// its flag ("--voxel: ..."). CLI11's NonNegativeNumber lets NaN through (NaN
// is not < 0) and unsigned options take "-1" as 2^64 - 1; these do not.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace sarmap::cli {

// A finite number >= 0 (doubles), or a whole number >= 0 (unsigned counts and seeds).
const CLI::Validator& finite_non_negative();
// A finite number > 0.
const CLI::Validator& finite_positive();

// `count` finite numbers separated by commas ("1,2.5,-3"), or nullopt.
std::optional<std::vector<double>> finite_number_list(const std::string& text, std::size_t count);

}  // namespace sarmap::cli
