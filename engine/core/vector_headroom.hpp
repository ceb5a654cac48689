// A vector sized for arrays that grow a little at every update (a map's
// columns, a grid over its extent): reallocated, with half again as much
// room, only when the new size outgrows it. Arrays made anew at each size
// leave the allocator holes a little too small for the next one. And the
// storage of one no longer needed, given back.
#pragma once

#include <cstddef>
#include <vector>

namespace sarmap {

// v becomes n copies of value, on its own storage while that holds n.
template <class T>
void assign_with_headroom(std::vector<T>& v, std::size_t n, const T& value) {
  if (v.capacity() < n) {
    v.clear();
    v.reserve(n + n / 2);
  }
  v.assign(n, value);
}

// v holds room for n, reallocated with half again as much when it holds less.
template <class T>
void reserve_with_headroom(std::vector<T>& v, std::size_t n) {
  if (v.capacity() < n) v.reserve(n + n / 2);
}

// v empty and holding no storage: for kept arrays whose region the map has
// forgotten, where headroom would keep memory for the area ever seen.
template <class T>
void release_storage(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

}  // namespace sarmap
