// Disjoint sets over 0..n-1 (union by size, path compression), for Kruskal's
// spanning forest and for tests that count connected components.
#pragma once

#include <cstddef>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace sarmap::topo {

class UnionFind {
 public:
  explicit UnionFind(std::size_t count) : parent_(count), size_(count, 1), set_count_(count) {
    std::iota(parent_.begin(), parent_.end(), std::uint32_t{0});
  }

  std::size_t element_count() const { return parent_.size(); }
  std::size_t set_count() const { return set_count_; }

  // Two passes (find the root, then point the whole path at it) rather than
  // recursion, so a long chain cannot overflow the stack.
  std::uint32_t find(std::uint32_t element) {
    std::uint32_t root = element;
    while (parent_[root] != root) root = parent_[root];
    while (parent_[element] != root) {
      const std::uint32_t next = parent_[element];
      parent_[element] = root;
      element = next;
    }
    return root;
  }

  // False when a and b were already in one set.
  bool unite(std::uint32_t a, std::uint32_t b) {
    std::uint32_t root_a = find(a);
    std::uint32_t root_b = find(b);
    if (root_a == root_b) return false;
    // The smaller tree goes under the larger, which keeps every tree's depth logarithmic.
    if (size_[root_a] < size_[root_b]) std::swap(root_a, root_b);
    parent_[root_b] = root_a;
    size_[root_a] += size_[root_b];
    --set_count_;
    return true;
  }

  bool connected(std::uint32_t a, std::uint32_t b) { return find(a) == find(b); }

 private:
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> size_;
  std::size_t set_count_;
};

}  // namespace sarmap::topo
