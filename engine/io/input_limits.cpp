#include "engine/io/input_limits.hpp"

#include "engine/core/error.hpp"

namespace sarmap {

void check_declared_points(std::uint64_t declared, const InputLimits& limits, const std::string& file) {
  if (declared > limits.max_points) {
    throw Error(ErrorCode::OutOfRange, file + ": the header declares " + std::to_string(declared) +
                                           " points, more than the limit of " + std::to_string(limits.max_points) +
                                           " per cloud (sarmap's --max-scan-points)");
  }
}

}  // namespace sarmap
