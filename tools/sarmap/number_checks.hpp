// Checks for the CLI's numeric options, so each bad value is refused naming
// its flag ("--voxel: ..."). CLI11's NonNegativeNumber lets NaN through (NaN
// is not < 0) and unsigned options take "-1" as 2^64 - 1; these do not.
#pragma once

#include <CLI/CLI.hpp>

namespace sarmap::cli {

// A finite number >= 0 (doubles), or a whole number >= 0 (unsigned counts and seeds).
const CLI::Validator& finite_non_negative();
// A finite number > 0.
const CLI::Validator& finite_positive();

}  // namespace sarmap::cli
