// The element count of an array shape read from a file header (npy,
// safetensors), in checked arithmetic: a shape such as (2^40, 2^40) must not
// wrap to 0 in size_t and pass for an empty array of a huge shape.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>

namespace sarmap {

// product(shape), or nullopt when product(shape) * element_bytes does not fit
// in size_t. A shape holding a 0 has 0 elements whatever its other sizes.
inline std::optional<std::size_t> checked_element_count(std::span<const std::size_t> shape,
                                                        std::size_t element_bytes) {
  if (std::find(shape.begin(), shape.end(), std::size_t{0}) != shape.end()) return 0;
  std::size_t count = 1;
  for (const std::size_t d : shape) {
    if (count > std::numeric_limits<std::size_t>::max() / element_bytes / d) return std::nullopt;
    count *= d;
  }
  return count;
}

}  // namespace sarmap
