// The bytes glibc's heap has handed out and not taken back (mallinfo2: the
// chunks in use in every arena, and those mapped on their own), for tests
// that check a structure's count of its own memory against the heap. The
// figure includes the allocator's few bytes per chunk and whatever its
// per-thread caches hold, so compare with a tolerance. Meaningless under the
// sanitizers, whose allocators glibc does not see (kSanitizedBuild).
//
// Call keep_arrays_in_the_heap() first: an array glibc maps on its own with
// a 2 MiB alignment (huge_page_allocator.hpp) counts the alignment's unused
// address space too, where an array in the heap leaves it as free chunks.
#pragma once

#include <malloc.h>

#include <cstddef>

namespace sarmap::test {

// Arrays up to glibc's largest mmap threshold (32 MiB) taken from the heap
// from now on, for the rest of the process.
inline void keep_arrays_in_the_heap() { mallopt(M_MMAP_THRESHOLD, 32 << 20); }

inline std::size_t live_heap_bytes() {
  const struct mallinfo2 heap = mallinfo2();
  return heap.uordblks + heap.hblkhd;
}

}  // namespace sarmap::test
