// Large arrays on huge pages: alignment, the bytes counted for them, the
// advice as the kernel recorded it (/proc/self/smaps), and reserving scratch
// in whole huge pages.
#include "engine/core/huge_page_allocator.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/core/aligned_vector.hpp"

namespace sarmap {
namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;

std::uintptr_t address(const void* p) { return reinterpret_cast<std::uintptr_t>(p); }

// The VmFlags line of the mapping holding p ("" if /proc/self/smaps has none).
std::string vm_flags_of(const void* p) {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> lo >> dash >> hi && dash == '-') {
      inside = lo <= address(p) && address(p) < hi;
    } else if (inside && line.rfind("VmFlags:", 0) == 0) {
      return line;
    }
  }
  return "";
}

TEST(HugePageAllocator, SmallArraysAreCacheLineAlignedAndCountedAsAsked) {
  for (const std::size_t bytes : {std::size_t{1}, std::size_t{1000}, kHugePageMinBytes - 1}) {
    void* p = allocate_array_bytes(bytes);
    EXPECT_EQ(address(p) % kSimdAlignment, 0u) << bytes;
    EXPECT_EQ(allocated_array_bytes(bytes), bytes);
    std::memset(p, 0xab, bytes);
    free_array_bytes(p, bytes);
  }
}

TEST(HugePageAllocator, LargeArraysTakeWholeAlignedHugePagesAdvisedAsHuge) {
  EXPECT_EQ(allocated_array_bytes(kHugePageMinBytes - 1), kHugePageMinBytes - 1);
  EXPECT_EQ(allocated_array_bytes(kHugePageMinBytes), kHugePageBytes);
  EXPECT_EQ(allocated_array_bytes(kHugePageBytes), kHugePageBytes);
  EXPECT_EQ(allocated_array_bytes(kHugePageBytes + 1), 2 * kHugePageBytes);
  EXPECT_EQ(allocated_array_bytes(3 * kMiB + 1), 4 * kMiB);

  const std::size_t bytes = 3 * kMiB + 1;
  auto* p = static_cast<unsigned char*>(allocate_array_bytes(bytes));
  EXPECT_EQ(address(p) % kHugePageBytes, 0u);
  std::memset(p, 0x5a, allocated_array_bytes(bytes));  // the whole pages are ours
  EXPECT_EQ(p[bytes - 1], 0x5a);
  const std::string flags = vm_flags_of(p);
  if (flags.empty()) {
    free_array_bytes(p, bytes);
    GTEST_SKIP() << "no /proc/self/smaps";
  }
  EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
  free_array_bytes(p, bytes);
}

TEST(HugePageAllocator, CapacityBytesCountWholeHugePages) {
  HugePageVector<std::uint32_t> small;
  small.reserve(1000);
  EXPECT_EQ(capacity_bytes(small), small.capacity() * sizeof(std::uint32_t));
  HugePageVector<std::uint32_t> large;
  large.reserve((3 * kMiB) / sizeof(std::uint32_t));
  EXPECT_EQ(capacity_bytes(large), 4 * kMiB);
}

TEST(HugePageAllocator, ScratchIsReservedInWholeHugePagesFromAnEighthOfOne) {
  HugePageVector<std::uint64_t> below;
  const std::size_t few = kHugePageBytes / 8 / sizeof(std::uint64_t) - 1;
  reserve_whole_huge_pages(below, few);
  EXPECT_EQ(below.capacity(), few);

  HugePageVector<std::uint64_t> eighth;
  reserve_whole_huge_pages(eighth, few + 1);
  EXPECT_EQ(eighth.capacity() * sizeof(std::uint64_t), kHugePageBytes);

  // Elements that do not divide a huge page: as many as fit.
  struct Twelve {
    std::uint32_t v[3];
  };
  HugePageVector<Twelve> odd;
  reserve_whole_huge_pages(odd, (5 * kMiB) / sizeof(Twelve));
  EXPECT_EQ(odd.capacity(), (6 * kMiB) / sizeof(Twelve));
  EXPECT_EQ(capacity_bytes(odd), 6 * kMiB);

  // Elements that leave bytes over in one huge page (2 MiB / 24 = 87,381
  // rest 8) still fill it, on huge pages.
  struct TwentyFour {
    double v[3];
  };
  HugePageVector<TwentyFour> rays;
  reserve_whole_huge_pages(rays, 15000);
  EXPECT_EQ(rays.capacity(), kHugePageBytes / sizeof(TwentyFour));
  EXPECT_EQ(capacity_bytes(rays), kHugePageBytes);
  EXPECT_EQ(address(rays.data()) % kHugePageBytes, 0u);

  // Never shrinks, and keeps what it holds.
  eighth.assign(10, 7);
  const std::size_t before = eighth.capacity();
  reserve_whole_huge_pages(eighth, 5);
  EXPECT_EQ(eighth.capacity(), before);
  EXPECT_EQ(eighth[9], 7u);
}

TEST(HugePageAllocator, ResizesInWholeHugePagesKeepingWhatItHolds) {
  HugePageVector<std::uint32_t> grid;
  resize_in_whole_huge_pages(grid, 3, 5u);
  EXPECT_EQ(grid, (HugePageVector<std::uint32_t>{5, 5, 5}));
  EXPECT_EQ(grid.capacity(), 3u);  // under an eighth of a huge page: as asked

  const std::size_t n = kHugePageBytes / 4 / sizeof(std::uint32_t) + 1;
  resize_in_whole_huge_pages(grid, n);
  ASSERT_EQ(grid.size(), n);
  EXPECT_EQ(grid[2], 5u);
  EXPECT_EQ(grid[3], 0u);
  EXPECT_EQ(grid[n - 1], 0u);
  EXPECT_EQ(grid.capacity() * sizeof(std::uint32_t), kHugePageBytes);
  EXPECT_EQ(address(grid.data()) % kHugePageBytes, 0u);

  resize_in_whole_huge_pages(grid, 2);  // shrinking keeps the room
  EXPECT_EQ(grid.size(), 2u);
  EXPECT_EQ(grid.capacity() * sizeof(std::uint32_t), kHugePageBytes);
}

}  // namespace
}  // namespace sarmap
