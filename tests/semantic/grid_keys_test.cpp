// Tests engine/semantic/grid_keys.hpp: column keys give back their indices,
// neighbouring columns and cells never share a key, and a coordinate's key
// is its floor cell's.
#include "engine/semantic/grid_keys.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <set>

namespace sarmap::grid_keys {
namespace {

TEST(GridKeys, ColumnKeysGiveBackTheirIndices) {
  const std::int64_t far = (std::int64_t{1} << 31) - 1;
  for (const std::int64_t cx : {std::int64_t{0}, std::int64_t{-1}, std::int64_t{7}, -far - 1, far}) {
    for (const std::int64_t cy : {std::int64_t{0}, std::int64_t{-1}, std::int64_t{-12345}, -far - 1, far}) {
      const std::uint64_t key = column_key(cx, cy);
      EXPECT_EQ(column_x(key), cx);
      EXPECT_EQ(column_y(key), cy);
    }
  }
}

TEST(GridKeys, NeighboursHaveDistinctKeys) {
  std::set<std::uint64_t> columns, cells;
  for (std::int64_t i = -2; i <= 2; ++i) {
    for (std::int64_t j = -2; j <= 2; ++j) {
      EXPECT_TRUE(columns.insert(column_key(i, j)).second);
      for (std::int64_t k = -2; k <= 2; ++k) EXPECT_TRUE(cells.insert(cell_key(i, j, k)).second);
    }
  }
  const std::int64_t edge = (std::int64_t{1} << 21) - 1;  // the cells' range ends
  EXPECT_NE(cell_key(-edge - 1, 0, 0), cell_key(edge, 0, 0));
  EXPECT_NE(cell_key(0, -edge - 1, edge), cell_key(0, edge, -edge - 1));
}

TEST(GridKeys, ACoordinatesKeyIsItsFloorCells) {
  EXPECT_EQ(index(0.25, 10.0), 2);
  EXPECT_EQ(index(-0.01, 10.0), -1);
  EXPECT_EQ(index(-0.1, 10.0), -1);
  EXPECT_EQ(column_key_of(-0.05, 0.35, 10.0), column_key(-1, 3));
  EXPECT_TRUE(in_reach(-kMaxHorizontal, kMaxHorizontal));
  EXPECT_FALSE(in_reach(2 * kMaxHorizontal, 0.0));
}

}  // namespace
}  // namespace sarmap::grid_keys
