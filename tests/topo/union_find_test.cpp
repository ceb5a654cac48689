// UnionFind against a plain relabelling of components, on random unions.
#include "engine/topo/union_find.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

namespace sarmap::topo {
namespace {

TEST(UnionFind, StartsWithEveryElementAlone) {
  UnionFind sets(4);
  EXPECT_EQ(sets.element_count(), 4u);
  EXPECT_EQ(sets.set_count(), 4u);
  for (std::uint32_t i = 0; i < 4; ++i) EXPECT_EQ(sets.find(i), i);
  EXPECT_FALSE(sets.connected(0, 1));
}

TEST(UnionFind, UniteReportsWhetherTwoSetsMerged) {
  UnionFind sets(5);
  EXPECT_TRUE(sets.unite(0, 1));
  EXPECT_TRUE(sets.unite(3, 4));
  EXPECT_FALSE(sets.unite(1, 0));
  EXPECT_TRUE(sets.unite(1, 4));
  EXPECT_FALSE(sets.unite(0, 3));
  EXPECT_FALSE(sets.unite(2, 2));
  EXPECT_EQ(sets.set_count(), 2u);
  EXPECT_TRUE(sets.connected(0, 4));
  EXPECT_FALSE(sets.connected(2, 4));
}

TEST(UnionFind, AgreesWithRelabellingOnRandomUnions) {
  std::mt19937 random(7);
  for (int round = 0; round < 50; ++round) {
    const std::uint32_t n = 1 + random() % 200;
    UnionFind sets(n);
    std::vector<std::uint32_t> label(n);
    for (std::uint32_t i = 0; i < n; ++i) label[i] = i;
    for (int k = 0; k < 300; ++k) {
      const std::uint32_t a = random() % n;
      const std::uint32_t b = random() % n;
      const bool separate = label[a] != label[b];
      EXPECT_EQ(sets.unite(a, b), separate);
      // By value: std::replace takes references, and label[b] is among the replaced.
      const std::uint32_t from = label[b];
      const std::uint32_t to = label[a];
      if (separate) std::replace(label.begin(), label.end(), from, to);
    }
    EXPECT_EQ(sets.set_count(), std::set<std::uint32_t>(label.begin(), label.end()).size());
    for (int k = 0; k < 100; ++k) {
      const std::uint32_t a = random() % n;
      const std::uint32_t b = random() % n;
      EXPECT_EQ(sets.connected(a, b), label[a] == label[b]);
    }
  }
}

TEST(UnionFind, LongChainDoesNotOverflowTheStack) {
  // Unions that would make a path of a million links without union by size.
  const std::uint32_t n = 1u << 20;
  UnionFind sets(n);
  for (std::uint32_t i = 1; i < n; ++i) sets.unite(i, i - 1);
  EXPECT_EQ(sets.set_count(), 1u);
  EXPECT_EQ(sets.find(0), sets.find(n - 1));
}

}  // namespace
}  // namespace sarmap::topo
