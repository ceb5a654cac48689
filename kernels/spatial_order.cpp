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
    std::uint32_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const float v = points[i * stride + a];
      const float q = std::isfinite(v) ? (v - lo[a]) * scale[a] : 0.0f;
      const auto cell = static_cast<std::uint32_t>(std::clamp(q, 0.0f, static_cast<float>((1 << kBitsPerAxis) - 1)));
      code |= spread_bits(cell) << a;
    }
    // Code above, index below: one integer sort, ties in index order.
    keys[i] = (std::uint64_t{code} << 32) | static_cast<std::uint64_t>(i);
  }
  std::sort(keys.data(), keys.data() + count);
  for (std::size_t i = 0; i < count; ++i) order[i] = static_cast<std::uint32_t>(keys[i] & 0xffffffffu);
}

}  // namespace sarmap::kernels
