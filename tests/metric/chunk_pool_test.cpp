// The pools the metric map's blocks take storage from: chunks given back are
// taken again before a new page, every page is counted, size classes fit.
#include "engine/metric/chunk_pool.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <vector>

namespace sarmap::metric {
namespace {

TEST(ChunkPool, ChunksGivenBackAreTakenBeforeANewPage) {
  ChunkPool<std::int16_t> pool(512);  // 1 KiB chunks, 16 to a page
  constexpr int kPerPage = 16;
  EXPECT_EQ(pool.memory_bytes(), 0u);
  std::vector<std::int16_t*> taken;
  for (int i = 0; i < kPerPage; ++i) taken.push_back(pool.take());
  EXPECT_EQ(std::set<std::int16_t*>(taken.begin(), taken.end()).size(), std::size_t{kPerPage});  // distinct
  for (std::size_t i = 1; i < taken.size(); ++i) EXPECT_GE(taken[i] - taken[i - 1], 512);
  const std::size_t one_page = pool.memory_bytes();
  EXPECT_GE(one_page, kPerPage * 1024u);
  EXPECT_EQ(pool.chunks_in_use(), std::size_t{kPerPage});
  pool.give(taken[10]);
  pool.give(taken[12]);
  EXPECT_EQ(pool.chunks_in_use(), std::size_t{kPerPage - 2});
  EXPECT_EQ(pool.take(), taken[12]);
  EXPECT_EQ(pool.take(), taken[10]);
  // No new page (the free list's own few bytes aside).
  const std::size_t after_reuse = pool.memory_bytes();
  EXPECT_LT(after_reuse, one_page + 1024);
  pool.take();  // one more opens a second page
  EXPECT_GE(pool.memory_bytes(), after_reuse + kPerPage * 1024u);
  EXPECT_EQ(pool.chunks_in_use(), std::size_t{kPerPage + 1});
}

TEST(SizeClassPool, ClassesArePowersOfTwoFromFourRows) {
  using Pool = SizeClassPool<std::int64_t, 512>;
  EXPECT_EQ(Pool::capacity_for(0), 0u);
  EXPECT_EQ(Pool::capacity_for(1), 4u);
  EXPECT_EQ(Pool::capacity_for(4), 4u);
  EXPECT_EQ(Pool::capacity_for(5), 8u);
  EXPECT_EQ(Pool::capacity_for(300), 512u);
  EXPECT_EQ(Pool::capacity_for(512), 512u);
  Pool pool;
  std::int64_t* small = pool.take(4);
  std::int64_t* large = pool.take(512);
  for (int i = 0; i < 512; ++i) large[i] = i;  // a whole chunk is usable
  for (int i = 0; i < 4; ++i) small[i] = -i;
  EXPECT_EQ(large[511], 511);
  pool.give(large, 512);
  EXPECT_EQ(pool.take(512), large);
  EXPECT_NE(pool.take(4), small);
}

}  // namespace
}  // namespace sarmap::metric
