#include "engine/semantic/dgcnn/repeated_rows.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>

namespace sarmap {

std::size_t find_repeated_rows(const float* rows, std::size_t n, std::size_t channels, RepeatedRows& out) {
  const std::size_t row_bytes = channels * sizeof(float);
  out.order.resize(n);
  out.row_of.resize(n);
  std::uint32_t* order = out.order.data();
  std::uint32_t* row_of = out.row_of.data();
  std::iota(order, order + n, 0u);
  // By bytes, then by index: each run of identical rows starts at its first appearance.
  std::sort(order, order + n, [&](std::uint32_t a, std::uint32_t b) {
    const int c = std::memcmp(rows + a * channels, rows + b * channels, row_bytes);
    return c != 0 ? c < 0 : a < b;
  });
  for (std::size_t s = 0; s < n; ++s) {
    const bool starts_run = s == 0 || std::memcmp(rows + order[s - 1] * channels, rows + order[s] * channels, row_bytes) != 0;
    row_of[order[s]] = starts_run ? order[s] : row_of[order[s - 1]];
  }
  // Number the distinct rows in order of first appearance; `order` now maps a
  // first appearance to its number.
  std::size_t distinct = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (row_of[i] == i) order[i] = static_cast<std::uint32_t>(distinct++);
    row_of[i] = order[row_of[i]];
  }
  if (distinct == n) return n;  // nothing repeats: the caller runs the rows as they are
  out.copies.resize(distinct);
  out.distinct.resize(distinct * channels);
  std::fill_n(out.copies.data(), distinct, 0u);
  for (std::size_t i = 0; i < n; ++i) {
    if (out.copies.data()[row_of[i]]++ == 0) {
      std::memcpy(out.distinct.data() + row_of[i] * channels, rows + i * channels, row_bytes);
    }
  }
  return distinct;
}

void keep_k_nearest_copies(std::uint32_t* neighbours, std::size_t rows, std::size_t k, const std::uint32_t* copies) {
  for (std::size_t i = 0; i < rows; ++i) {
    std::uint32_t* list = neighbours + i * k;
    std::size_t held = 0, kept = 0;
    while (kept < k && held < k) held += copies[list[kept++]];
    std::fill(list + kept, list + k, list[0]);
  }
}

}  // namespace sarmap
