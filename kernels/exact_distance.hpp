// The distance both kNN paths rank by in the end: squared Euclidean in
// double, summed in one fixed order, so the kernel of every instruction set
// and the scalar reference agree on every neighbour, ties included.
#pragma once

#include <cstddef>

namespace sarmap::kernels {

// Eight independent partial sums (one chain of dependent adds was a fifth
// of the 64-d kernel's time), combined pairwise, in the same order on every
// build; the files that include this are compiled with -ffp-contract=off so
// no build fuses the square into an FMA with different rounding.
inline double exact_squared_distance(const float* a, const float* b, std::size_t dim) {
  constexpr std::size_t kLanes = 8;
  double partial[kLanes] = {};
  std::size_t j = 0;
  for (; j + kLanes <= dim; j += kLanes) {
    for (std::size_t l = 0; l < kLanes; ++l) {
      const double diff = static_cast<double>(a[j + l]) - static_cast<double>(b[j + l]);
      partial[l] += diff * diff;
    }
  }
  for (std::size_t l = 0; j < dim; ++j, ++l) {
    const double diff = static_cast<double>(a[j]) - static_cast<double>(b[j]);
    partial[l] += diff * diff;
  }
  return ((partial[0] + partial[1]) + (partial[2] + partial[3])) +
         ((partial[4] + partial[5]) + (partial[6] + partial[7]));
}

}  // namespace sarmap::kernels
