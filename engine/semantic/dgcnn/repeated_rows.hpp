// A block with fewer points than the model takes is filled by drawing some
// points again (block_sampling.hpp), so up to all but one of its rows repeat
// others. Every layer computes the same values for identical rows, and the
// max over neighbours does not count repeats, so the network can run on each
// distinct row once, provided each row's neighbour list keeps exactly the
// distinct points that the k nearest of the repeated block would hold.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/aligned_buffer.hpp"

namespace sarmap {

struct RepeatedRows {
  kernels::AlignedBuffer<float> distinct;         // the distinct rows, in order of first appearance
  kernels::AlignedBuffer<std::uint32_t> copies;   // per distinct row: how often it appears
  kernels::AlignedBuffer<std::uint32_t> row_of;   // per input row: its distinct row
  kernels::AlignedBuffer<std::uint32_t> order;    // scratch: the rows sorted by their bytes

  std::size_t bytes() const {
    return distinct.capacity_bytes() + copies.capacity_bytes() + row_of.capacity_bytes() + order.capacity_bytes();
  }
};

// Finds the rows of `rows` (n x channels, row-major) that are bitwise
// identical and returns the number of distinct rows; when it is below n,
// fills `out` (row_of is filled in any case). Rows equal
// in value but not in bits (0.0 and -0.0) count as distinct, which only
// costs the time of running both.
std::size_t find_repeated_rows(const float* rows, std::size_t n, std::size_t channels, RepeatedRows& out);

// neighbours (rows x k, nearest first, as kernels::knn gives them over the
// distinct rows): keeps in each list the entries up to the one at which the
// copies of the entries so far first reach k, and fills the rest of the list
// with its first entry. The kept entries are the distinct points among the k
// nearest of the block with every row repeated copies[row] times, except
// where two distinct points lie at exactly the same distance at the k-th
// place (the repeated block breaks that tie copy by copy, by index).
void keep_k_nearest_copies(std::uint32_t* neighbours, std::size_t rows, std::size_t k, const std::uint32_t* copies);

}  // namespace sarmap
