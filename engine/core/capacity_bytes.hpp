// Bytes a container holds on the heap, by capacity rather than size: what
// the structures that report their own memory (the metric map, the ray
// integrator's scratch) add up, so their figures count allocations, not use.
#pragma once

#include <cstddef>
#include <vector>

namespace sarmap {

template <class T, class Allocator>
std::size_t capacity_bytes(const std::vector<T, Allocator>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace sarmap
