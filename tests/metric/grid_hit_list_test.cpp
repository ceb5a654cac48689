// The hits listed by block of a scan's dense grid, against a plain listing
// (every grid block's hits found by scanning all ends, in end order): random
// ends over a grid with negative block coordinates, no hits, every end a
// hit, and the refusal when a hit lies outside the grid on any side.
#include "engine/metric/grid_hit_list.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace sarmap::metric {
namespace {

// Grid block g's hits, found the plain way.
std::vector<std::uint32_t> plain_hits_of_block(const kernels::DenseMaskGrid& grid, std::size_t g,
                                               const std::vector<VoxelKey>& ends,
                                               const std::vector<std::uint8_t>& is_hit) {
  std::vector<std::uint32_t> hits;
  for (std::uint32_t u = 0; u < ends.size(); ++u) {
    if (!is_hit[u]) continue;
    const BlockKey b = block_of(ends[u]);
    const std::size_t i = static_cast<std::size_t>(b.x - grid.first_block[0]);
    const std::size_t j = static_cast<std::size_t>(b.y - grid.first_block[1]);
    const std::size_t k = static_cast<std::size_t>(b.z - grid.first_block[2]);
    const auto bx = static_cast<std::size_t>(grid.blocks[0]), by = static_cast<std::size_t>(grid.blocks[1]);
    if (i + bx * (j + by * k) == g) hits.push_back(u);
  }
  return hits;
}

void expect_listed_as_plain(const GridHitList& list, const kernels::DenseMaskGrid& grid,
                            const std::vector<VoxelKey>& ends, const std::vector<std::uint8_t>& is_hit) {
  ASSERT_TRUE(list.listed());
  std::size_t hits = 0;
  for (const std::uint8_t h : is_hit) hits += h;
  const std::size_t blocks = kernels::dense_grid_blocks(grid);
  EXPECT_EQ(list.begin(0), 0u);
  EXPECT_EQ(list.begin(blocks), hits);
  EXPECT_EQ(list.hits().size(), hits);
  for (std::size_t g = 0; g < blocks; ++g) {
    const std::vector<std::uint32_t> listed(list.hits().begin() + list.begin(g),
                                            list.hits().begin() + list.begin(g + 1));
    EXPECT_EQ(listed, plain_hits_of_block(grid, g, ends, is_hit)) << "grid block " << g;
  }
}

// A grid of 5 x 3 x 4 blocks from block (-2, -1, 3), and ends inside it.
struct RandomEnds {
  kernels::DenseMaskGrid grid{{-2, -1, 3}, {5, 3, 4}, nullptr};
  std::vector<VoxelKey> ends;
  std::vector<std::uint8_t> is_hit;

  RandomEnds(std::size_t count, double hit_fraction, unsigned seed) {
    std::mt19937 rng(seed);
    const auto within = [&](int axis) {
      const int first = grid.first_block[axis] * kBlockEdge;
      return std::uniform_int_distribution<int>(first, first + grid.blocks[axis] * kBlockEdge - 1)(rng);
    };
    std::bernoulli_distribution hit(hit_fraction);
    for (std::size_t u = 0; u < count; ++u) {
      ends.push_back({within(0), within(1), within(2)});
      is_hit.push_back(hit(rng) ? 1 : 0);
    }
  }
};

TEST(GridHitList, ListsEachBlocksHitsInEndOrderAsThePlainListing) {
  for (const double hit_fraction : {0.0, 0.3, 1.0}) {
    SCOPED_TRACE(::testing::Message() << "hit fraction " << hit_fraction);
    const RandomEnds scan(2000, hit_fraction, 7);
    GridHitList list;
    ASSERT_TRUE(list.build(scan.grid, scan.ends, scan.is_hit));
    expect_listed_as_plain(list, scan.grid, scan.ends, scan.is_hit);
  }
}

TEST(GridHitList, NoEndsListNothing) {
  const kernels::DenseMaskGrid grid{{0, 0, 0}, {2, 2, 2}, nullptr};
  GridHitList list;
  ASSERT_TRUE(list.build(grid, {}, {}));
  expect_listed_as_plain(list, grid, {}, {});
}

TEST(GridHitList, RefusesAHitOutsideTheGridOnAnySideButNotAMiss) {
  RandomEnds scan(200, 0.5, 11);
  GridHitList list;
  const kernels::DenseMaskGrid& grid = scan.grid;
  for (int axis = 0; axis < 3; ++axis) {
    for (const bool after : {false, true}) {
      SCOPED_TRACE(::testing::Message() << "axis " << axis << (after ? ", after the grid" : ", before the grid"));
      VoxelKey outside = scan.ends.front();
      const int first = grid.first_block[axis] * kBlockEdge;
      const int beyond = after ? first + grid.blocks[axis] * kBlockEdge : first - 1;
      (axis == 0 ? outside.x : axis == 1 ? outside.y : outside.z) = beyond;
      std::vector<VoxelKey> ends = scan.ends;
      std::vector<std::uint8_t> is_hit = scan.is_hit;
      ends.push_back(outside);
      is_hit.push_back(0);  // a ray's end that is no hit may lie anywhere
      ASSERT_TRUE(list.build(grid, ends, is_hit));
      expect_listed_as_plain(list, grid, ends, is_hit);
      is_hit.back() = 1;
      EXPECT_FALSE(list.build(grid, ends, is_hit));
      EXPECT_FALSE(list.listed());
    }
  }
  // Listed again after a refusal, and forgotten by clear().
  ASSERT_TRUE(list.build(grid, scan.ends, scan.is_hit));
  expect_listed_as_plain(list, grid, scan.ends, scan.is_hit);
  list.clear();
  EXPECT_FALSE(list.listed());
}

}  // namespace
}  // namespace sarmap::metric
