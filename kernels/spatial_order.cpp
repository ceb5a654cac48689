#include "kernels/spatial_order.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

// The position of cell (x[0], x[1], x[2]) along a 3-D Hilbert curve over
// 2^10 cells per axis (Skilling's transform, "Programming the Hilbert curve",
// 2004: the coordinates become the index's bits, which are interleaved with
// axis 0 the most significant of each triple). Unlike a Morton curve, which
// jumps across the box at every power-of-two boundary, consecutive cells of
// a Hilbert curve are neighbours, so runs of points along it have smaller
// boxes — which is what lets the kNN kernel skip more panels (in 64-d a tile
// visits about a fifth fewer). Branch-free: the bit tests are masks.
std::uint32_t hilbert_index(std::uint32_t x[3]) {
  for (std::uint32_t q = 1u << (kBitsPerAxis - 1); q > 1; q >>= 1) {
    const std::uint32_t p = q - 1;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t set = 0u - ((x[i] & q) != 0 ? 1u : 0u);  // all ones when bit q of x[i] is set
      const std::uint32_t swap = (x[0] ^ x[i]) & p & ~set;         // exchange the low bits of x[0] and x[i]
      x[0] ^= (p & set) | swap;                                     // or invert x[0]'s low bits
      x[i] ^= swap;
    }
  }
  // Gray encoding.
  x[1] ^= x[0];
  x[2] ^= x[1];
  std::uint32_t t = 0;
  for (std::uint32_t q = 1u << (kBitsPerAxis - 1); q > 1; q >>= 1) t ^= (x[2] & q) != 0 ? q - 1 : 0u;
  for (int i = 0; i < 3; ++i) x[i] ^= t;
  return (spread_bits(x[0]) << 2) | (spread_bits(x[1]) << 1) | spread_bits(x[2]);
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
  keys.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t cell[3];
    for (int a = 0; a < 3; ++a) {
      const float v = points[i * stride + a];
      const float q = std::isfinite(v) ? (v - lo[a]) * scale[a] : 0.0f;
      cell[a] = static_cast<std::uint32_t>(std::clamp(q, 0.0f, static_cast<float>((1 << kBitsPerAxis) - 1)));
    }
    const std::uint32_t code = hilbert_index(cell);
    // Code above, index below: one integer sort, ties in index order.
    keys[i] = (std::uint64_t{code} << 32) | static_cast<std::uint64_t>(i);
  }
  std::sort(keys.data(), keys.data() + count);
  for (std::size_t i = 0; i < count; ++i) order[i] = static_cast<std::uint32_t>(keys[i] & 0xffffffffu);
}

}  // namespace sarmap::kernels
