#include "kernels/spatial_order.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace sarmap::kernels {
namespace {

constexpr int kBitsPerAxis = 10;

// Spreads the low 10 bits of v so that two zero bits follow each one.
std::uint32_t spread_bits(std::uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

// Points whose Hilbert indices are computed together, each step across
// all of them, so that the compiler turns the steps into vector code.
constexpr std::size_t kLanes = 16;

// code[l] = the position of cell (x[0][l], x[1][l], x[2][l]) along a 3-D
// Hilbert curve over 2^10 cells per axis (Skilling's transform, "Programming
// the Hilbert curve", 2004: the coordinates become the index's bits, which
// are interleaved with axis 0 the most significant of each triple). Unlike a
// Morton curve, which jumps across the box at every power-of-two boundary,
// consecutive cells of a Hilbert curve are neighbours, so runs of points
// along it have smaller boxes — which is what lets the kNN kernel skip more
// panels (in 64-d a tile visits about a fifth fewer). Branch-free: the bit
// tests are masks.
void hilbert_indices(std::uint32_t (&x)[3][kLanes], std::uint32_t (&code)[kLanes]) {
  for (std::uint32_t q = 1u << (kBitsPerAxis - 1); q > 1; q >>= 1) {
    const std::uint32_t p = q - 1;
    for (int i = 0; i < 3; ++i) {
      for (std::size_t l = 0; l < kLanes; ++l) {
        const std::uint32_t set = 0u - ((x[i][l] & q) >> (__builtin_ctz(q)));  // all ones when bit q of x[i] is set
        const std::uint32_t swap = (x[0][l] ^ x[i][l]) & p & ~set;             // exchange the low bits of x[0] and x[i]
        x[0][l] ^= (p & set) | swap;                                            // or invert x[0]'s low bits
        x[i][l] ^= swap;
      }
    }
  }
  for (std::size_t l = 0; l < kLanes; ++l) {
    // Gray encoding.
    x[1][l] ^= x[0][l];
    x[2][l] ^= x[1][l];
    std::uint32_t t = 0;
    for (std::uint32_t q = 1u << (kBitsPerAxis - 1); q > 1; q >>= 1) t ^= (0u - ((x[2][l] & q) >> __builtin_ctz(q))) & (q - 1);
    for (int i = 0; i < 3; ++i) x[i][l] ^= t;
    code[l] = (spread_bits(x[0][l]) << 2) | (spread_bits(x[1][l]) << 1) | spread_bits(x[2][l]);
  }
}

// Sorts keys[0..count) by their bits 32..61 (the codes), stably, so equal
// codes keep the index order of the low bits; a least-significant-digit radix
// sort, three passes of 10 bits, through `spare` (count more keys). Returns
// where the sorted keys are. std::sort was a large part of spatial_order().
std::uint64_t* sort_by_code(std::uint64_t* keys, std::uint64_t* spare, std::size_t count) {
  constexpr int kDigitBits = 10;
  constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
  static_assert(3 * kDigitBits == 3 * kBitsPerAxis, "three digits cover the code");
  std::uint32_t start[kBuckets];
  for (int pass = 0; pass < 3; ++pass) {
    const int shift = 32 + pass * kDigitBits;
    std::fill_n(start, kBuckets, 0u);
    for (std::size_t i = 0; i < count; ++i) ++start[(keys[i] >> shift) & (kBuckets - 1)];
    std::uint32_t sum = 0;
    for (std::size_t b = 0; b < kBuckets; ++b) sum += std::exchange(start[b], sum);
    for (std::size_t i = 0; i < count; ++i) spare[start[(keys[i] >> shift) & (kBuckets - 1)]++] = keys[i];
    std::swap(keys, spare);
  }
  return keys;
}

}  // namespace

void spatial_order(const float* points, std::size_t stride, std::size_t count, AlignedBuffer<std::uint64_t>& keys,
                   std::uint32_t* order) {
  float lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::numeric_limits<float>::infinity();
    hi[a] = -std::numeric_limits<float>::infinity();
  }
  for (std::size_t i = 0; i < count; ++i) {
    for (int a = 0; a < 3; ++a) {
      const float v = points[i * stride + a];
      if (!std::isfinite(v)) continue;
      lo[a] = std::min(lo[a], v);
      hi[a] = std::max(hi[a], v);
    }
  }
  float scale[3];
  for (int a = 0; a < 3; ++a) {
    const float extent = hi[a] - lo[a];
    // An axis without finite values or without extent quantises to 0.
    scale[a] = std::isfinite(extent) && extent > 0.0f ? static_cast<float>((1 << kBitsPerAxis) - 1) / extent : 0.0f;
    if (!std::isfinite(lo[a])) lo[a] = 0.0f;
  }
  // Two arrays of keys: the radix sort's source and destination.
  keys.resize(2 * count);
  for (std::size_t first = 0; first < count; first += kLanes) {
    std::uint32_t cell[3][kLanes] = {};
    const std::size_t lanes = std::min(kLanes, count - first);
    for (std::size_t l = 0; l < lanes; ++l) {
      for (int a = 0; a < 3; ++a) {
        const float v = points[(first + l) * stride + a];
        const float q = std::isfinite(v) ? (v - lo[a]) * scale[a] : 0.0f;
        cell[a][l] = static_cast<std::uint32_t>(std::clamp(q, 0.0f, static_cast<float>((1 << kBitsPerAxis) - 1)));
      }
    }
    std::uint32_t code[kLanes];
    hilbert_indices(cell, code);
    // Code above, index below: sorted by code, ties in index order.
    for (std::size_t l = 0; l < lanes; ++l) keys[first + l] = (std::uint64_t{code[l]} << 32) | (first + l);
  }
  const std::uint64_t* sorted = sort_by_code(keys.data(), keys.data() + count, count);
  for (std::size_t i = 0; i < count; ++i) order[i] = static_cast<std::uint32_t>(sorted[i] & 0xffffffffu);
}

}  // namespace sarmap::kernels
