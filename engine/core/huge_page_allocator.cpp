#include "engine/core/huge_page_allocator.hpp"

#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "engine/core/aligned_vector.hpp"

namespace sarmap {

std::size_t allocated_array_bytes(std::size_t bytes) {
  if (bytes < kHugePageMinBytes) return bytes;
  return (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
}

void* allocate_array_bytes(std::size_t bytes) {
  if (bytes < kHugePageMinBytes) return ::operator new(bytes, std::align_val_t{kSimdAlignment});
  const std::size_t whole = allocated_array_bytes(bytes);
  if (whole < bytes) throw std::bad_alloc();  // bytes near SIZE_MAX
  void* storage = std::aligned_alloc(kHugePageBytes, whole);
  if (storage == nullptr) throw std::bad_alloc();
#if defined(MADV_HUGEPAGE)
  // Only advice: refused (no THP in this kernel) it leaves ordinary pages.
  (void)madvise(storage, whole, MADV_HUGEPAGE);
#endif
  return storage;
}

void free_array_bytes(void* storage, std::size_t bytes) noexcept {
  if (bytes < kHugePageMinBytes) {
    ::operator delete(storage, std::align_val_t{kSimdAlignment});
  } else {
    std::free(storage);
  }
}

}  // namespace sarmap
