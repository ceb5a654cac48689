// Storage for large arrays on transparent huge pages: an array of 1.75 MiB
// or more starts on a 2 MiB boundary and its pages are advised as huge
// (madvise MADV_HUGEPAGE; the kernel's THP setting "madvise" or "always"),
// so its first touch costs one fault per 2 MiB instead of one per 4 KiB and
// its random accesses miss the TLB less. A first touch is what makes a
// fresh process's first scans slow (the integrator's scratch, the key
// tables as they grow), and a page fault is dearer in a virtual machine
// than on bare metal. Smaller arrays are plain 64-byte aligned allocations.
// Where the kernel has no huge pages, the advice is ignored and only the
// alignment remains. An array that is not a multiple of 2 MiB holds its
// last huge page whole once touched: allocated_array_bytes() counts it, and
// capacity_bytes() of a HugePageVector reports that (the key tables, powers
// of two, are exact multiples).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "engine/core/capacity_bytes.hpp"

namespace sarmap {

inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;
// Arrays from here up take whole huge pages: an eighth below a huge page, so
// that as many elements as fill whole huge pages qualify whatever their
// size (2 MiB / 24 bytes leaves 8 bytes over), at most an eighth wasted.
inline constexpr std::size_t kHugePageMinBytes = kHugePageBytes - kHugePageBytes / 8;

// bytes of storage aligned to 64 bytes, on huge pages from kHugePageMinBytes
// up; throws std::bad_alloc.
void* allocate_array_bytes(std::size_t bytes);
// Frees what allocate_array_bytes(bytes) returned, with the same bytes.
void free_array_bytes(void* storage, std::size_t bytes) noexcept;
// Bytes allocate_array_bytes(bytes) takes: whole huge pages from kHugePageMinBytes up.
std::size_t allocated_array_bytes(std::size_t bytes);

template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() noexcept = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) { return static_cast<T*>(allocate_array_bytes(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { free_array_bytes(p, n * sizeof(T)); }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
};

template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

template <class T>
std::size_t capacity_bytes(const HugePageVector<T>& v) {
  return allocated_array_bytes(v.capacity() * sizeof(T));
}

// Room for n elements; from an eighth of a huge page up, as many as fill
// whole huge pages. For scratch that grows over a run's first scans: its
// pages then come a huge page at a time (up to 2 MiB more than it needs).
template <class T>
void reserve_whole_huge_pages(HugePageVector<T>& v, std::size_t n) {
  if (n <= v.capacity()) return;
  const std::size_t bytes = n * sizeof(T);
  if (bytes >= kHugePageBytes / 8) n = std::max(n, allocated_array_bytes(std::max(bytes, kHugePageBytes)) / sizeof(T));
  v.reserve(n);
}

// resize(n, value) with room reserved as reserve_whole_huge_pages reserves
// it: for scratch that grows with the scan and is resized, not refilled.
template <class T>
void resize_in_whole_huge_pages(HugePageVector<T>& v, std::size_t n, const T& value = T{}) {
  reserve_whole_huge_pages(v, n);
  v.resize(n, value);
}

}  // namespace sarmap
